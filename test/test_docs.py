#!/usr/bin/python3
"""The README and docs/*.md as a reader uses them: every relative link and image resolves (and each
#anchor names a heading of its target, as GitHub makes the anchors), every repo path written in
backticks exists, and every command in their code blocks names what the package has: a script that
is executable, a launch file and its arguments, an executable the package builds or installs, a
service or topic the nodelet advertises, a message, an `amcr_offline` option, a dynamic_reconfigure
parameter. The README stays at most README_MAX_LINES lines, no page cites an issue number (say the
feature or the reason instead), and the parameter table of docs/configuration.md agrees with
config/amcr.yaml and cfg/AMCR.cfg. The checkers are tested on broken pages too, so each can fail.

  test/test_docs.py [--xml FILE]   (JUnit XML for catkin; about 1 s)
"""
import os
import sys
import unittest

import yaml

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from docs_checks import (  # noqa: E402 (the checkers live beside this file)
    HERE,
    PACKAGE,
    README,
    README_MAX_LINES,
    check_command,
    check_commands,
    check_issue_numbers,
    check_links,
    check_parameter_table,
    check_paths,
    check_readme_length,
    commands,
    documents,
    github_anchor,
    read,
    reconfigure_parameters,
    rosrun_executables,
    split_markdown,
    written_by_hand,
)


class Documents(unittest.TestCase):
    def test_links_and_images_resolve(self):
        problems = [p for path in documents() for p in check_links(path, read(path))]
        self.assertEqual(problems, [], "\n".join(problems))

    def test_repo_paths_in_backticks_exist(self):
        problems = [p for path in documents() for p in check_paths(path, read(path))]
        self.assertEqual(problems, [], "\n".join(problems))

    def test_commands_name_what_the_package_has(self):
        problems = [p for path in documents() if written_by_hand(path) for p in check_commands(path, read(path))]
        self.assertEqual(problems, [], "\n".join(problems))

    def test_no_issue_numbers(self):
        problems = [p for path in documents() if written_by_hand(path) for p in check_issue_numbers(path, read(path))]
        self.assertEqual(problems, [], "\n".join(problems))

    def test_readme_is_short(self):
        problems = check_readme_length(read(README))
        self.assertEqual(problems, [], "\n".join(problems))

    def test_the_readme_has_commands_to_check(self):
        # A README whose code blocks this test no longer understands would pass for nothing.
        _, blocks = split_markdown(read(README))
        found = [c for start, lines in blocks for _, c in commands(lines, start)]
        self.assertTrue(any(c.startswith("scripts/") for c in found), found)
        self.assertTrue(any(c.startswith("roslaunch amcr ") for c in found), found)
        self.assertTrue(any(c.startswith("rosservice call ") for c in found), found)

    def test_parameter_table_agrees_with_the_configuration(self):
        with open(os.path.join(PACKAGE, "config", "amcr.yaml")) as f:
            defaults = yaml.safe_load(f)
        problems = check_parameter_table(read(os.path.join(PACKAGE, "docs", "configuration.md")), defaults,
                                         reconfigure_parameters())
        self.assertEqual(problems, [], "\n".join(problems))


class TheChecksCatch(unittest.TestCase):
    """Each checker on a page with the mistake it is there for: it must report it."""

    PAGE = os.path.join(PACKAGE, "docs", "a-page.md")

    def test_a_missing_file_an_image_and_an_anchor(self):
        self.assertEqual(check_links(self.PAGE, "# A page\n\nSee [how](how-it-works.md#where-each-step-lives).\n"), [])
        self.assertEqual(len(check_links(self.PAGE, "See [x](no-such-page.md).\n")), 1)
        self.assertEqual(len(check_links(self.PAGE, "![picture](images/no-such.png)\n")), 1)
        self.assertEqual(len(check_links(self.PAGE, "See [x](how-it-works.md#no-such-heading).\n")), 1)
        self.assertEqual(len(check_links(self.PAGE, "# Up\n\nSee [x](#down).\n")), 1)
        self.assertEqual(check_links(self.PAGE, "# Down: here\n\nSee [x](#down-here).\n"), [])
        self.assertEqual(check_links(self.PAGE, "```\n[x](nowhere.md)\n```\n"), [], "links in code are text")

    def test_github_anchors(self):
        self.assertEqual(github_anchor("Where recall is lost: the funnel"), "where-recall-is-lost-the-funnel")
        self.assertEqual(github_anchor("The offline runner: `amcr_offline`"), "the-offline-runner-amcr_offline")
        self.assertEqual(github_anchor("Several objects, copies, a new instance"), "several-objects-copies-a-new-instance")

    def test_a_missing_path(self):
        self.assertEqual(check_paths(self.PAGE, "`src/ros/recognizer_ros.cpp`, `fuzz/corpus/<target>/`\n"), [])
        self.assertEqual(len(check_paths(self.PAGE, "the file `src/core/no_such_file.cpp`\n")), 1)
        self.assertEqual(len(check_paths(self.PAGE, "run `bench/no_such_tool --seed 1`\n")), 1)
        self.assertEqual(len(check_paths(self.PAGE, "`fuzz/corpus/<target>/no-such-seed`\n")), 1)

    def test_commands_of_what_does_not_exist(self):
        executables = rosrun_executables()
        self.assertEqual(check_command("scripts/test --sanitize", executables), [])
        broken = ["scripts/no_such_script", "scripts/lib/setup.sh", "roslaunch amcr no_such.launch",
                  "roslaunch amcr amcr.launch no_such_argument:=1", "rosrun amcr no_such_node",
                  "rosrun amcr amcr_offline --no-such-flag 1", "rosservice call /amcr/no_such_service",
                  "rostopic echo /amcr/no_such_topic", "rostopic echo /somewhere/else", "rosmsg show amcr/NoSuch",
                  "rosrun dynamic_reconfigure dynparam set /amcr no_such_parameter 1",
                  ".build/ws/devel/lib/amcr/amcr_offline --input x --overlay-video y",
                  "rosrun amcr amcr_teach --label mug --no-such-flag"]
        for command in broken:
            with self.subTest(command=command):
                self.assertNotEqual(check_command(command, executables), [], command)

    def test_commands_in_blocks_and_inline(self):
        page = ("```\nscripts/demo --seed 2   # a comment\nrosrun amcr no_such \\\n    --flag\n"
                "python3 - <<'EOF'\nrosrun amcr not_checked_in_a_heredoc\nEOF\n```\n"
                "Or `rosservice call /amcr/no_such`.\n")
        problems = check_commands(self.PAGE, page)
        self.assertEqual(len(problems), 2, problems)

    def test_issue_numbers(self):
        self.assertEqual(len(check_issue_numbers(self.PAGE, "as in issue 14, and (issue 18, item 2); Issue #7\n")), 3)
        self.assertEqual(check_issue_numbers(self.PAGE, "an issue of size, 14 issues\n"), [])

    def test_a_long_readme(self):
        self.assertEqual(len(check_readme_length("line\n" * (README_MAX_LINES + 1))), 1)
        self.assertEqual(check_readme_length("line\n" * README_MAX_LINES), [])

    def test_a_parameter_table_that_disagrees(self):
        reconfigure = {"a": ("int_t", "1", 1.0, 5.0), "b": ("double_t", "0.5", 0.001, 10.0), "c": ("bool_t", "True", None, None)}
        head = "| parameter | default | range | unit | what |\n|---|---|---|---|---|\n"
        good = head + "| `a` | 1 | [1, 5] | | |\n| `b` | 0.5 | (0, 10] | | |\n| `c` | 1 | switch | | |\n"
        self.assertEqual(check_parameter_table(good, {"a": 1, "b": 0.5, "c": 1}, reconfigure), [])
        self.assertEqual(len(check_parameter_table(good, {"a": 2, "b": 0.5, "c": 1}, reconfigure)), 1)
        self.assertEqual(len(check_parameter_table(good, {"a": 1, "b": 0.5, "c": 1, "d": 3}, reconfigure)), 1)
        self.assertEqual(len(check_parameter_table(good.replace("[1, 5]", "[1, 6]"), {"a": 1, "b": 0.5, "c": 1}, reconfigure)), 1)
        self.assertEqual(len(check_parameter_table(good.replace("`c` | 1 | switch", "`c` | 1 | [0, 1]"),
                                                   {"a": 1, "b": 0.5, "c": 1}, reconfigure)), 1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(HERE, "bench"))
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_docs"))
