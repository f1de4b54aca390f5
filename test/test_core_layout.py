#!/usr/bin/python3
"""The core library's folders form layers: a file of include/amcr/<folder>/ or src/core/<folder>/
includes headers of its own folder and of the folders below it, never above; no header includes
itself through others, and no two units (x.h with x.cpp) include each other; no class holds more
than MAX_MEMBERS data members; RecognizerRos (the nodelet's glue) stays under ROS_GLUE_LINES; no file of src/
or include/ is longer than MAX_LINES; every public header is in a folder or is one of the library's
face (FACE, at the top of include/amcr/).

  test/test_core_layout.py [--xml FILE]   (JUnit XML for catkin; well under a second)
"""
import collections
import os
import re
import sys
import unittest

# The folders of include/amcr and src/core, lowest first: each may include only itself and the
# folders above it in this list.
LAYERS = [
    ("base", "geometry, parameters, errors, random streams, threads, resource bounds: used by all"),
    ("io", "image and parameter files, byte streams, prototype directories: files, not the method"),
    ("scan", "the radial edge scans (spec 'Radial edge scans'): what a particle reads of an image"),
    ("memory", "the prototypes, their lookup tables (spec 'Lookup tables'), the memory and its prior"),
    ("filter", "V- and M-particles: motion model Q, observation model O, resampling (paper 3.6, 4.1-4.3)"),
    ("extraction", "objects out of the particle clusters, fitted, verified and tracked (spec 'Output')"),
]
# The library's face, at the top of include/amcr/ (and src/core/): it may include every folder.
FACE = ["recognizer.h", "recognizer_session.h", "overlay.h", "frame_budget.h", "working_scale.h"]
# The longest file of src/ and include/: one idea a file.
MAX_LINES = 450

HERE = os.path.dirname(os.path.realpath(__file__))
PACKAGE = os.path.dirname(HERE)
PUBLIC = os.path.join(PACKAGE, "include", "amcr")
CORE = os.path.join(PACKAGE, "src", "core")
TOP = "(top)"  # the folder of the face
RANK = {name: k for k, (name, _) in enumerate(LAYERS)}
RANK[TOP] = len(LAYERS)
INCLUDE = re.compile(r'^\s*#\s*include\s*(?:"([^"]+)"|<(amcr/[^>]+)>)', re.M)


def files_under(root, extensions):
    found = []
    for folder, _, names in os.walk(root):
        found += [os.path.join(folder, n) for n in names if n.endswith(extensions)]
    return sorted(found)


def folder_of(path):
    """The layer of a file of include/amcr or src/core: its first folder there, or TOP."""
    for root in (PUBLIC, CORE):
        if path.startswith(root + os.sep):
            parts = os.path.relpath(path, root).split(os.sep)
            return parts[0] if len(parts) > 1 else TOP
    raise ValueError(path + " is neither in include/amcr nor in src/core")


def resolve(including, name, angled):
    """The file an include names: amcr/... in include/; a private header beside the including
    file, else under src/core (the core's private include directory); None when there is none."""
    if angled or name.startswith("amcr/"):
        path = os.path.join(PACKAGE, "include", name)
        return path if os.path.isfile(path) else None
    for base in (os.path.dirname(including), CORE):
        path = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(path):
            return path
    return None


def include_graph():
    """{file: [(included file or None, the include's text)]} over include/amcr and src/core."""
    graph = {}
    for path in files_under(PUBLIC, (".h",)) + files_under(CORE, (".h", ".cpp")):
        with open(path) as f:
            text = f.read()
        edges = []
        for quoted, angled in INCLUDE.findall(text):
            name = quoted or angled
            edges.append((resolve(path, name, bool(angled)), name))
        graph[path] = edges
    return graph


def short(path):
    return os.path.relpath(path, PACKAGE)


def find_cycles(graph):
    """The cycles a depth-first walk of `graph` ({node: nodes it points to}) meets, each as the list
    of its nodes with the first repeated at the end."""
    state = collections.defaultdict(int)  # 0 unseen, 1 on the path, 2 done
    cycles = []

    def visit(node, path):
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state[nxt] == 1:
                cycles.append(path[path.index(nxt):] + [nxt])
            elif state[nxt] == 0:
                visit(nxt, path)
        path.pop()
        state[node] = 2

    for node in sorted(graph):
        if state[node] == 0:
            visit(node, [])
    return cycles


class Layers(unittest.TestCase):
    maxDiff = None

    def test_every_folder_is_declared(self):
        for root in (PUBLIC, CORE):
            folders = sorted(n for n in os.listdir(root) if os.path.isdir(os.path.join(root, n)))
            self.assertEqual([f for f in folders if f not in RANK], [], "folders of %s not in LAYERS" % short(root))
        self.assertEqual(len(RANK), len(LAYERS) + 1, "a folder is declared twice")

    def test_every_include_resolves(self):
        unresolved = ["%s: %s" % (short(path), name)
                      for path, edges in include_graph().items() for target, name in edges if target is None]
        self.assertEqual(unresolved, [])

    def test_folders_include_only_themselves_and_folders_below(self):
        upward = []
        for path, edges in include_graph().items():
            here = folder_of(path)
            for target, name in edges:
                if target is None:
                    continue
                there = folder_of(target)
                if RANK[there] > RANK[here]:
                    upward.append("%s (%s) includes %s (%s, above)" % (short(path), here, name, there))
        self.assertEqual(upward, [], "\n".join(upward))

    def test_no_include_cycle(self):
        graph = {path: {t for t, _ in edges if t is not None} for path, edges in include_graph().items()}
        cycles = [" -> ".join(short(p) for p in cycle) for cycle in find_cycles(graph)]
        self.assertEqual(cycles, [], "\n".join(cycles))

    def test_no_include_cycle_between_units(self):
        """A unit is a header and the sources of its name (x.h, x.cpp): one of them including the
        other's header, and the other including the first's, is a cycle between two ideas even
        when no header includes itself (x.cpp -> y.h, y.cpp -> x.h)."""
        def unit(path):
            return os.path.splitext(os.path.basename(path))[0]
        graph = collections.defaultdict(set)
        for path, edges in include_graph().items():
            for target, _ in edges:
                if target is not None and unit(target) != unit(path):
                    graph[unit(path)].add(unit(target))
        cycles = [" -> ".join(cycle) for cycle in find_cycles(graph)]
        self.assertEqual(cycles, [], "\n".join(cycles))

    def test_every_public_header_is_in_a_folder_or_the_face(self):
        loose = sorted(n for n in os.listdir(PUBLIC) if os.path.isfile(os.path.join(PUBLIC, n)))
        self.assertEqual(sorted(set(loose) - set(FACE)), [], "headers at the top of include/amcr not in FACE")
        self.assertEqual(sorted(set(FACE) - set(loose)), [], "FACE names headers that are not there")

    def test_a_source_lies_in_the_folder_of_its_header(self):
        headers = {}
        for path in files_under(PUBLIC, (".h",)):
            headers[os.path.splitext(os.path.basename(path))[0]] = folder_of(path)
        misplaced = []
        for path in files_under(CORE, (".cpp",)):
            name = os.path.splitext(os.path.basename(path))[0]
            if name in headers and headers[name] != folder_of(path):
                misplaced.append("%s: its header is in %s" % (short(path), headers[name]))
        self.assertEqual(misplaced, [])


# A class of the core holds at most MAX_MEMBERS data members (its own state, named with a trailing
# underscore, the project's style; plain structs of named fields are not counted). A class that needs
# more holds collaborators with state of their own (ParticleFilter: particle_filter.h).
MAX_MEMBERS = 12
CLASS = re.compile(r"^(?:class|struct)\s+(\w+)[^;{]*\{", re.M)
MEMBER = re.compile(r"^\s+(?!return\b|using\b|friend\b|typedef\b)[\w:<>,\s*&\[\]]+?\b(\w+_)\s*"
                    r"(?:=[^;]*|\{[^;]*\}|\[[^\]]*\])?;")


def class_members(text):
    """{class name: its data members named with a trailing underscore} of a header's text."""
    classes = {}
    for match in CLASS.finditer(text):
        depth, end = 1, match.end()
        while depth and end < len(text):
            depth += {"{": 1, "}": -1}.get(text[end], 0)
            end += 1
        names = set()
        for line in text[match.end():end - 1].split("\n"):
            code = line.split("//")[0]
            found = MEMBER.match(code)
            if found and "(" not in code:
                names.add(found.group(1))
        classes[match.group(1)] = names
    return classes


class ClassSize(unittest.TestCase):
    maxDiff = None

    def test_no_class_of_the_core_holds_too_many_data_members(self):
        counts = {}
        for path in files_under(PUBLIC, (".h",)) + files_under(CORE, (".h",)):
            with open(path) as f:
                for name, members in class_members(f.read()).items():
                    counts[name] = max(counts.get(name, 0), len(members))
        too_many = ["%s: %d data members (at most %d)" % (name, n, MAX_MEMBERS)
                    for name, n in sorted(counts.items()) if n > MAX_MEMBERS]
        self.assertEqual(too_many, [], "\n".join(too_many))

    def test_the_member_count_sees_members(self):
        text = ("class Counted\n{\npublic:\n  int get() const { return a_; }\n\nprivate:\n  int a_ = 0;\n"
                "  std::vector<std::pair<int, int>> b_;  // a comment\n  cv::Mat c_;\n  double d_[3];\n"
                "  static constexpr int kNotAMember = 1;\n  void helper(int x_);\n};\n")
        self.assertEqual(class_members(text), {"Counted": {"a_", "b_", "c_", "d_"}})


# The core's functions and classes that take or keep the whole Params (params.h), by file: what builds
# everything from it, what reads it by name or from a file, and what is still to be given its groups.
# Every other component takes the group(s) of Params it reads (ObservationParams, ScanParams, ...), to
# which a Params binds. "*": the whole file (the parameters' own table and file).
WHOLE_PARAMS = {
    "include/amcr/base/params.h": "*",  # the table by name, the checks
    "src/core/base/params.cpp": "*",
    "include/amcr/io/params_file.h": "*",  # the parameter file
    "src/core/io/params_file.cpp": "*",
    # The recognizer builds every component from the whole Params and keeps them for params().
    "include/amcr/recognizer.h": {"Recognizer", "params", "params_"},
    "src/core/recognizer.cpp": {"Recognizer::Recognizer"},
    # A memory made ready for a filter's Params, handed to ParticleFilter with them; the look-alike
    # pairs are built with the attention's, the extraction's, the index's, the threads and the cache's.
    "include/amcr/filter/filter_memory.h": {"FilterMemory", "params", "params_"},
    "src/core/filter/filter_memory.cpp": {"FilterMemory::FilterMemory", "buildPlaces"},
    # The filter builds its collaborators, each from the groups it reads, and shows the Params of its
    # memory; the two models keep an overload for the whole Params, which the tests use.
    "include/amcr/filter/particle_filter.h": {"ParticleFilter", "params"},
    "src/core/filter/particle_filter.cpp": {"ParticleFilter::ParticleFilter"},
    "include/amcr/filter/observation_model.h": {"ObservationModel"},
    "include/amcr/filter/motion_model.h": {"MotionModel"},
    # The session owns and edits the recognizer's parameters: it hands them to each rebuild whole.
    "include/amcr/recognizer_session.h": {"RecognizerSession", "ReconfigurationFrom", "params", "params_"},
    "src/core/recognizer_session.cpp": {"RecognizerSession::RecognizerSession", "RecognizerSession::params", "params_"},
}
PARAMS_TYPE = re.compile(r"\bParams\b")


def without_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def whole_params_users(text):
    """The names in C++ `text` that take or keep a whole Params: the function (or std::function alias)
    whose parameter list holds it, else the variable, member or function it declares."""
    text = without_comments(text)
    names = set()
    for match in PARAMS_TYPE.finditer(text):
        after = text[match.end():]
        if re.match(r"\s*(::|:|\{)", after):
            continue  # Params' own members, its definition
        depth, i = 0, match.start() - 1
        while i >= 0 and text[i] not in ";{}":
            depth += {")": 1, "(": -1}.get(text[i], 0)
            if depth < 0:
                break
            i -= 1
        if i >= 0 and text[i] == "(":
            start = max(text.rfind(c, 0, i) for c in ";{}") + 1
            alias = re.match(r"\s*using\s+(\w+)\s*=", text[start:i])
            function = re.search(r"([\w:~]+)\s*$", text[:i])
            names.add(alias.group(1) if alias else function.group(1) if function else "(lambda)")
        else:
            declared = re.match(r"\s*(?:const\s*)?[&*]?\s*>?\s*([\w:]+)", after)  # also a shared_ptr<const Params>
            if declared:
                names.add(declared.group(1))
    return names


class WholeParams(unittest.TestCase):
    maxDiff = None

    def test_only_the_listed_functions_take_the_whole_params(self):
        found = {}
        for path in files_under(PUBLIC, (".h",)) + files_under(CORE, (".h", ".cpp")):
            with open(path) as f:
                names = whole_params_users(f.read())
            if names and WHOLE_PARAMS.get(short(path)) != "*":
                found[short(path)] = names
        extra = ["%s: %s" % (path, ", ".join(sorted(names - set(WHOLE_PARAMS.get(path, ())))))
                 for path, names in sorted(found.items()) if names - set(WHOLE_PARAMS.get(path, ()))]
        self.assertEqual(extra, [], "take the whole Params where they read one group or two (pass the groups):\n" +
                         "\n".join(extra))
        stale = ["%s: %s" % (path, ", ".join(sorted(set(names) - found.get(path, set()))))
                 for path, names in sorted(WHOLE_PARAMS.items())
                 if names != "*" and set(names) - found.get(path, set())]
        self.assertEqual(stale, [], "WHOLE_PARAMS names what no longer takes the whole Params: drop it\n" +
                         "\n".join(stale))

    def test_the_search_sees_parameters_members_and_aliases(self):
        text = ("// Params in a comment\nvoid f(int a, const Params& p);\nstruct S\n{\n  Params params_;\n"
                "  const Params& params() const;\n  using Reader = std::function<void(const Params&)>;\n"
                "  void g(const ScanParams& s, cv::flann::IndexParams i);\n  std::shared_ptr<const Params> kept_;\n};\n"
                "void Params::validate() const;\n")
        self.assertEqual(whole_params_users(text), {"f", "params_", "params", "Reader", "kept_"})


# Every parameter is declared once: a field of one group of params.h (Params inherits them all), one
# entry of the table by name (params.cpp: numericParameters() or wordParameters()), one key of
# config/amcr.yaml and one entry of cfg/AMCR.cfg (but NOT_RECONFIGURABLE).
NOT_RECONFIGURABLE = {"table_cache_dir"}  # read when the memory is loaded (cfg/AMCR.cfg says so)
STRUCT = re.compile(r"^struct\s+(\w+)\s*(?::\s*([\w\s,]+?))?\s*\{(.*?)^\};", re.M | re.S)
FIELD = re.compile(r"^\s+[\w:<>,\s]+?\b(\w+)\s*(?:=[^;]*)?;", re.M)


def parameter_groups():
    """{group: [its fields]} of the structs Params inherits (each base's own fields), and Params' own."""
    with open(os.path.join(PUBLIC, "base", "params.h")) as f:
        text = without_comments(f.read())
    structs = {m.group(1): ([b.strip() for b in (m.group(2) or "").split(",") if b.strip()],
                            [n for n in FIELD.findall(m.group(3)) if n != "validate"])
               for m in STRUCT.finditer(text)}
    groups, pending = {}, list(structs.get("Params", ([], []))[0])
    while pending:
        name = pending.pop(0)
        bases, fields = structs[name]
        groups[name] = fields
        pending += bases
    return groups, structs.get("Params", ([], []))[1]


def names_in(path, pattern, functions=()):
    """The names `pattern` finds in the file at `path`, or in the bodies of its `functions` only."""
    with open(os.path.join(PACKAGE, path)) as f:
        text = f.read()
    if functions:
        text = without_comments(text)
        text = "".join(re.search(r"\b%s\(\)\s*\{.*?^\}" % name, text, re.M | re.S).group(0) for name in functions)
    return re.findall(pattern, text, re.M)


class ParameterDeclarations(unittest.TestCase):
    maxDiff = None

    def test_every_field_is_in_one_group_and_declared_once_everywhere(self):
        groups, own = parameter_groups()
        self.assertGreater(len(groups), 5, "params.h: no groups found (struct Params : ParticleCounts, ...)")
        self.assertEqual(own, [], "Params declares fields of its own: put them in a group")
        fields = collections.Counter(n for names in groups.values() for n in names)
        self.assertEqual([n for n, k in fields.items() if k > 1], [], "fields in two groups")
        table = collections.Counter(names_in("src/core/base/params.cpp", r'(?:AMCR_(?:INT|DOUBLE)\(|choice\("|\{\{")(\w+)',
                                             ("numericParameters", "wordParameters")))
        yaml = collections.Counter(names_in("config/amcr.yaml", r"^(\w+):"))
        cfg = collections.Counter(names_in("cfg/AMCR.cfg", r'(?:\badd\(\s*\w+,\s*|\.add\(\s*)"(\w+)"'))
        for what, declared, expected in (("params.cpp's table", table, set(fields)),
                                         ("config/amcr.yaml", yaml, set(fields)),
                                         ("cfg/AMCR.cfg", cfg, set(fields) - NOT_RECONFIGURABLE)):
            self.assertEqual(sorted(expected - set(declared)), [], "fields missing from " + what)
            self.assertEqual(sorted(set(declared) - expected), [], "in %s but no field of a group" % what)
            self.assertEqual([n for n, k in declared.items() if k > 1], [], "declared twice in " + what)

    def test_the_parameters_that_build_the_tables_are_the_memory_groups(self):
        # What tablesDiffer compares (buildsTables in params.cpp) is what MemoryParams and its EdgeParams
        # hold, but where the cache lies: a field added to either group and not marked would never rebuild
        # the tables when it changes.
        groups, _ = parameter_groups()
        marked = set(names_in("src/core/base/params.cpp", r"buildsTables\(AMCR_(?:INT|DOUBLE)\((\w+)"))
        self.assertEqual(sorted(marked), sorted((set(groups["MemoryParams"]) | set(groups["EdgeParams"])) - {"table_cache_dir"}))


class FileLength(unittest.TestCase):
    maxDiff = None

    def test_no_file_of_src_or_include_is_too_long(self):
        long_files = []
        for root in ("src", "include"):
            for path in files_under(os.path.join(PACKAGE, root), (".h", ".hpp", ".cpp", ".py")):
                with open(path) as f:
                    lines = sum(1 for _ in f)
                if lines > MAX_LINES:
                    long_files.append("%s: %d lines" % (short(path), lines))
        self.assertEqual(long_files, [], "over %d lines:\n%s" % (MAX_LINES, "\n".join(long_files)))


# The nodelet's RecognizerRos is glue over amcr::RecognizerSession (recognizer_session.h): services,
# messages, diagnostics and dynamic_reconfigure, no recognition logic. Its files together stay under
# ROS_GLUE_LINES, and none of them reaches into the filter.
ROS_GLUE = ("src/ros/recognizer_ros.h", "src/ros/recognizer_ros.cpp", "src/ros/recognizer_services.cpp")
ROS_GLUE_LINES = 500


class RosGlue(unittest.TestCase):
    def test_recognizer_ros_is_under_its_line_budget(self):
        counts = {}
        for path in ROS_GLUE:
            with open(os.path.join(PACKAGE, path)) as f:
                counts[path] = sum(1 for _ in f)
        self.assertLess(sum(counts.values()), ROS_GLUE_LINES,
                        "RecognizerRos's files: %s; move the logic into the core's session" % counts)

    def test_recognizer_ros_does_not_reach_into_the_filter(self):
        reaching = []
        for path in ROS_GLUE:
            with open(os.path.join(PACKAGE, path)) as f:
                reaching += ["%s: %s" % (path, line.strip()) for line in f if line.startswith('#include "amcr/filter/')]
        self.assertEqual(reaching, [], "\n".join(reaching))


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(HERE, "bench"))
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_core_layout"))
