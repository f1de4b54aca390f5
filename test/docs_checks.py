"""What test/test_docs.py checks in README.md and docs/*.md, one checker a kind of reference:
links and anchors, repo paths, commands, issue numbers, the README's length, the parameter table.
Each checker takes a page's path and text and returns its problems, one line each, naming the line."""
import glob
import os
import re
import shlex
import sys
import unittest

import yaml

HERE = os.path.dirname(os.path.realpath(__file__))
PACKAGE = os.path.dirname(HERE)
README = os.path.join(PACKAGE, "README.md")
README_MAX_LINES = 320
# Written by the benchmark (bench/report.py) and the soak (bench/soak_report.py), not by hand: their
# links, anchors and paths are checked, their prose and commands are the generators'.
GENERATED = {"benchmark-latest.md", "soak-latest.md"}
# Top-level folders of the repository: a word in backticks that starts with one of them is a path.
REPO_DIRS = ("src", "include", "scripts", "launch", "config", "msg", "srv", "cfg", "test", "bench", "docs", "fuzz")
REPO_PATH = re.compile(r"(?:^|(?<=[\s\"'(=,]))((?:%s)/[^\s\"'`),;]*)" % "|".join(REPO_DIRS))
ISSUE_NUMBER = re.compile(r"\bissues?\s*#?\s*\d+", re.IGNORECASE)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def documents():
    """README.md and every docs/*.md."""
    return [README] + sorted(glob.glob(os.path.join(PACKAGE, "docs", "*.md")))


def written_by_hand(path):
    return os.path.basename(path) not in GENERATED


def relative(path):
    return os.path.relpath(path, PACKAGE)


# ------------------------------------------------------------------------------------------------
# Markdown: fenced code blocks apart from the prose, inline code spans, headings and their anchors.

def split_markdown(text):
    """Returns (prose lines, code blocks): prose as (line number, text) with fenced blocks left out,
    each code block as (line number of its first line, [lines])."""
    prose, blocks, block, fence = [], [], None, None
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if fence is None and stripped.startswith(("```", "~~~")):
            fence, block = stripped[:3], (number + 1, [])
        elif fence is not None and stripped.startswith(fence):
            blocks.append(block)
            fence, block = None, None
        elif fence is not None:
            block[1].append(line)
        else:
            prose.append((number, line))
    if block is not None:
        blocks.append(block)
    return prose, blocks


INLINE_CODE = re.compile(r"(`+)(.+?)\1")
LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\]]*\])*)\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def without_code(line):
    return INLINE_CODE.sub("", line)


def inline_code(prose):
    for number, line in prose:
        for match in INLINE_CODE.finditer(line):
            yield number, match.group(2).strip()


def github_anchor(heading):
    """The anchor GitHub gives a heading: its text as rendered (no code marks, emphasis or link
    targets), lower case, punctuation but '-' and '_' dropped, spaces turned into '-'."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = text.replace("`", "").replace("*", "")
    text = re.sub(r"<[^>]+>", "", text).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(text):
    """The anchors of a Markdown text's headings (repeated headings get -1, -2, ... as on GitHub)."""
    prose, _ = split_markdown(text)
    seen, result = {}, set()
    for _, line in prose:
        match = re.match(r"^ {0,3}#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not match:
            continue
        anchor = github_anchor(match.group(1))
        count = seen.get(anchor, 0)
        seen[anchor] = count + 1
        result.add(anchor if count == 0 else "%s-%d" % (anchor, count))
    return result


# ------------------------------------------------------------------------------------------------
# What the package has, read from its own files.

def built_executables():
    """Targets of add_executable in CMakeLists.txt."""
    return set(re.findall(r"add_executable\(\s*(\w+)", read(os.path.join(PACKAGE, "CMakeLists.txt"))))


def installed_scripts():
    """The scripts catkin_install_python installs (their file names)."""
    names = set()
    for block in re.findall(r"catkin_install_python\(\s*PROGRAMS(.*?)DESTINATION", read(os.path.join(PACKAGE, "CMakeLists.txt")), re.S):
        names.update(os.path.basename(path) for path in block.split())
    return names


def rosrun_executables():
    return built_executables() | installed_scripts()


def ros_sources():
    return "\n".join(read(path) for path in sorted(glob.glob(os.path.join(PACKAGE, "src", "ros", "*.cpp"))))


def advertised_services():
    return set(re.findall(r"advertiseService\s*(?:<[^(]*>)?\s*\(\s*\"(\w+)\"", ros_sources()))


def advertised_topics():
    return set(re.findall(r"\badvertise\s*(?:<[^(]*>)?\s*\(\s*\"(\w+)\"", ros_sources()))


def global_topics():
    """Topics outside the node's namespace that the nodelet publishes through a library."""
    sources = ros_sources() + "\n".join(read(path) for path in glob.glob(os.path.join(PACKAGE, "src", "ros", "*.h")))
    topics = set()
    if "diagnostic_updater::Updater" in sources:
        topics.add("/diagnostics")
    if "TransformBroadcaster" in sources:
        topics.add("/tf")
    return topics


def offline_options():
    """amcr_offline's options (src/offline/runner_options.cpp): the ones with a value and --help/-h."""
    text = read(os.path.join(PACKAGE, "src", "offline", "runner_options.cpp"))
    match = re.search(r"kValueOptions\[\]\s*=\s*\{([^}]*)\}", text)
    names = set(re.findall(r"\"([\w-]+)\"", match.group(1))) if match else set()
    for spec in re.findall(r"add_options\(\)\(\"([\w,-]+)\"", text):
        long_name, _, short = spec.partition(",")
        names.add(long_name)
        if short:
            names.add(short)
    return names


def reconfigure_parameters():
    """The parameters of cfg/AMCR.cfg: {name: (kind, default, lo, hi)} (lo, hi None for switches/words)."""
    text = read(os.path.join(PACKAGE, "cfg", "AMCR.cfg"))
    result = {}
    for name, kind, default, lo, hi in re.findall(
            r"\badd\(\s*\w+,\s*\"(\w+)\",\s*(\w+),\s*\w+,\s*(?:\"[^\"]*\"\s*)+,\s*([^,]+),\s*([^,]+),\s*([^)]+)\)", text):
        result[name] = (kind, default.strip(), float(lo), float(hi))
    for name, kind, default in re.findall(r"\.add\(\"(\w+)\",\s*(\w+),\s*\w+,\s*(?:\"[^\"]*\"\s*)+,\s*([^,)]+)", text):
        result[name] = (kind, default.strip(), None, None)
    return result


def launch_arguments(path):
    return set(re.findall(r"<arg\s+name=\"(\w+)\"", read(path)))


def script_options(path):
    """The --options an argparse script declares."""
    return set(re.findall(r"add_argument\(\s*\"(--[\w-]+)\"", read(path)))


# ------------------------------------------------------------------------------------------------
# The checks: each returns a list of problems, one line each, naming the file and the line.

def check_links(path, text):
    problems = []
    prose, _ = split_markdown(text)
    for number, line in prose:
        for match in LINK.finditer(without_code(line)):
            target = match.group(2)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            where = "%s:%d: link '%s'" % (relative(path), number, target)
            if resolved == path:
                if anchor and anchor not in anchors(text):
                    problems.append("%s: this page has no heading with the anchor '#%s'" % (where, anchor))
            elif not os.path.exists(resolved):
                problems.append("%s: no such file %s" % (where, relative(resolved)))
            elif anchor:
                if not resolved.endswith(".md"):
                    problems.append("%s: an anchor into a file that is not Markdown" % where)
                elif anchor not in anchors(read(resolved)):
                    problems.append("%s: %s has no heading with the anchor '#%s'" % (where, relative(resolved), anchor))
    return problems


def check_paths(path, text):
    """Repo paths in inline code (<name> stands for any name: fuzz/corpus/<target>/)."""
    problems = []
    prose, _ = split_markdown(text)
    for number, code in inline_code(prose):
        for match in REPO_PATH.finditer(code):
            candidate = match.group(1).rstrip(".:")
            pattern = re.sub(r"<[^>]*>", "*", candidate)
            full = os.path.join(PACKAGE, pattern)
            if not (glob.glob(full) if "*" in pattern else os.path.exists(full)):
                problems.append("%s:%d: `%s`: no such path in the repository" % (relative(path), number, candidate))
    return problems


def commands(code_lines, first_line=1):
    """The commands of a shell code block as (line number, command): continuation lines joined,
    here-documents and comments dropped, split at &&, ||, ; and |."""
    joined, pending, pending_line, heredoc = [], "", None, None
    for number, line in enumerate(code_lines, first_line):
        if heredoc is not None:
            if line.strip() == heredoc:
                heredoc = None
            continue
        marker = re.search(r"<<-?\s*['\"]?(\w+)['\"]?", line)
        if marker:
            heredoc = marker.group(1)
        line = re.sub(r"(^|\s)#.*$", "", line).rstrip()
        if pending_line is None:
            pending_line = number
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        joined.append((pending_line, pending + line))
        pending, pending_line = "", None
    if pending:
        joined.append((pending_line, pending))
    result = []
    for number, line in joined:
        for part in re.split(r"&&|\|\||;|\|", line):
            part = part.strip()
            if part:
                result.append((number, part))
    return result


def check_command(command, executables):
    """Problems of one command line (an empty list for commands this test does not know)."""
    try:
        words = shlex.split(command)
    except ValueError:
        words = command.split()
    if not words:
        return []
    head, args = words[0], words[1:]
    problems = []
    if head.startswith(tuple(d + "/" for d in REPO_DIRS)):
        full = os.path.join(PACKAGE, head)
        if not os.path.isfile(full):
            problems.append("'%s': no such file" % head)
        elif not os.access(full, os.X_OK):
            problems.append("'%s' is not executable" % head)
        elif head.startswith("scripts/") and os.path.basename(head) in installed_scripts() | {"amcr_teach"}:
            problems += check_script_options(full, args)
    elif re.search(r"(^|/)devel/lib/amcr/\w+$", head):
        name = os.path.basename(head)
        if name not in built_executables():
            problems.append("'%s': the package builds no executable '%s'" % (head, name))
        elif name == "amcr_offline":
            problems += check_offline_options(args)
    elif head == "amcr_offline":
        problems += check_offline_options(args)
    elif head == "roslaunch" and len(args) >= 2 and args[0] == "amcr":
        launch = os.path.join(PACKAGE, "launch", args[1])
        if not os.path.isfile(launch):
            problems.append("roslaunch amcr %s: no launch/%s" % (args[1], args[1]))
        else:
            declared = launch_arguments(launch)
            for arg in args[2:]:
                name = arg.split(":=", 1)[0]
                if ":=" in arg and name not in declared:
                    problems.append("roslaunch amcr %s: no argument '%s' in launch/%s" % (args[1], name, args[1]))
    elif head == "rosrun" and len(args) >= 2 and args[0] == "amcr":
        if args[1] not in executables:
            problems.append("rosrun amcr %s: the package builds or installs no such executable" % args[1])
        elif args[1] == "amcr_offline":
            problems += check_offline_options(args[2:])
        elif args[1] in installed_scripts():
            problems += check_script_options(os.path.join(PACKAGE, "scripts", args[1]), args[2:])
    elif head == "rosrun" and args[:3] == ["dynamic_reconfigure", "dynparam", "set"] and len(args) >= 5:
        if args[4] not in reconfigure_parameters():
            problems.append("dynparam set %s: cfg/AMCR.cfg has no parameter '%s'" % (args[3], args[4]))
    elif head == "rosservice" and len(args) >= 2 and args[0] == "call":
        name = args[1].rstrip("/").split("/")[-1]
        if name not in advertised_services():
            problems.append("rosservice call %s: the nodelet advertises no service '%s'" % (args[1], name))
    elif head == "rostopic" and len(args) >= 2 and args[0] in ("echo", "hz", "info", "bw", "delay"):
        topic = args[1]
        parts = topic.strip("/").split("/")
        if topic in global_topics():
            pass
        elif "amcr" in parts[:-1]:
            if parts[-1] not in advertised_topics():
                problems.append("rostopic %s %s: the nodelet advertises no topic '%s'" % (args[0], topic, parts[-1]))
        else:
            problems.append("rostopic %s %s: neither the nodelet's topic nor one it publishes" % (args[0], topic))
    elif head in ("rosmsg", "rossrv") and len(args) >= 2 and args[0] == "show" and args[1].startswith("amcr/"):
        folder, ext = ("msg", ".msg") if head == "rosmsg" else ("srv", ".srv")
        name = args[1].split("/", 1)[1]
        if not os.path.isfile(os.path.join(PACKAGE, folder, name + ext)):
            problems.append("%s show %s: no %s/%s%s" % (head, args[1], folder, name, ext))
    return problems


def option_names(args):
    names = []
    for arg in args:
        if arg == "--":
            break
        if arg.startswith("-") and not re.match(r"^-\d", arg):
            names.append(arg.split("=", 1)[0].lstrip("-"))
    return names


def check_offline_options(args):
    known = offline_options()
    return ["amcr_offline: no option '--%s' (src/offline/runner_options.cpp)" % name
            for name in option_names(args) if name not in known]


def check_script_options(script, args):
    declared = script_options(script)
    if not declared:
        return []
    return ["%s: no option '--%s'" % (os.path.basename(script), name)
            for name in option_names(args) if "--" + name not in declared and name not in ("h", "help")]


COMMAND_WORDS = ("rosrun ", "roslaunch ", "rosservice ", "rostopic ", "rosmsg ", "rossrv ", "amcr_offline ")


def check_commands(path, text, inline_too=True):
    """Commands in code blocks and, with inline_too, inline code that is a command."""
    problems = []
    executables = rosrun_executables()
    prose, blocks = split_markdown(text)
    found = [item for start, lines in blocks for item in commands(lines, start)]
    if inline_too:
        # Inline code is a command when it starts with a ROS command, or runs a script with arguments
        # (`bench/report.py` alone names a file).
        found += [(number, code) for number, code in inline_code(prose)
                  if code.startswith(COMMAND_WORDS) or (code.startswith(("scripts/", "bench/")) and " " in code)]
    for number, command in found:
        problems += ["%s:%d: %s" % (relative(path), number, problem) for problem in check_command(command, executables)]
    return problems


def check_issue_numbers(path, text):
    return ["%s:%d: cites an issue number ('%s'): name the feature or the reason" % (relative(path), number, match.group(0))
            for number, line in enumerate(text.splitlines(), 1) for match in ISSUE_NUMBER.finditer(line)]


def check_readme_length(text):
    lines = len(text.splitlines())
    return [] if lines <= README_MAX_LINES else ["README.md has %d lines (at most %d)" % (lines, README_MAX_LINES)]


def parameter_rows(text):
    """{name: (default cell, range cell)} of the Markdown table whose header starts '| parameter |'."""
    rows, in_table = {}, False
    for line in text.splitlines():
        if line.startswith("| parameter |"):
            in_table = True
            continue
        if in_table and not line.startswith("|"):
            break
        if in_table and not line.startswith("|---"):
            cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
            match = re.match(r"^`(\w+)`$", cells[0])
            if match:
                rows[match.group(1)] = (cells[1], cells[2])
    return rows


def check_parameter_table(text, defaults, reconfigure):
    """The table lists every key of config/amcr.yaml with its default, and the range of cfg/AMCR.cfg."""
    rows = parameter_rows(text)
    problems = []
    if not rows:
        return ["no '| parameter |' table"]
    for name in defaults:
        if name not in rows:
            problems.append("parameter '%s' of config/amcr.yaml is not in the table" % name)
    for name, (default_cell, range_cell) in rows.items():
        if name not in defaults:
            problems.append("parameter '%s' is not in config/amcr.yaml" % name)
            continue
        try:
            written = yaml.safe_load(default_cell)
        except yaml.YAMLError:
            written = default_cell
        if written != defaults[name]:
            problems.append("parameter '%s': default %r in the table, %r in config/amcr.yaml" % (name, written, defaults[name]))
        match = re.match(r"^[\[(]\s*([-+0-9.e]+)\s*,\s*([-+0-9.e]+)\s*\]$", range_cell)
        if match:
            if name not in reconfigure or reconfigure[name][2] is None:
                problems.append("parameter '%s': a range in the table, none in cfg/AMCR.cfg" % name)
            elif (float(match.group(1)), float(match.group(2))) != reconfigure[name][2:]:
                lo, hi = reconfigure[name][2:]
                if not (range_cell.startswith("(") and float(match.group(1)) == 0 and lo > 0 and float(match.group(2)) == hi):
                    problems.append("parameter '%s': range %s in the table, [%g, %g] in cfg/AMCR.cfg" % (name, range_cell, lo, hi))
        elif range_cell == "switch" and reconfigure.get(name, ("",))[0] != "bool_t":
            problems.append("parameter '%s': a switch in the table, not a bool_t in cfg/AMCR.cfg" % name)
    return problems


# ------------------------------------------------------------------------------------------------
