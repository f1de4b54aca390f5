#!/usr/bin/python3
"""The package as ROS tools see it: the parameter files are plain YAML that rosparam
reads with the values amcr::loadParams reads (numbers stay numbers), and catkin_lint finds nothing
wrong with CMakeLists.txt and package.xml. catkin_lint is Debian's catkin-lint (scripts/test
installs it); without it that case skips with a message.

  test/test_package_files.py [--xml FILE]   (JUnit XML for catkin; about 2 s)
"""
import os
import re
import shutil
import subprocess
import sys
import unittest

import yaml

HERE = os.path.dirname(os.path.realpath(__file__))
PACKAGE = os.path.dirname(HERE)
CONFIGS = [os.path.join(PACKAGE, "config", name) for name in ("amcr.yaml", "large_memory.yaml")]
# The parameters whose values are words (amcr::Params' enums and the cache directory).
WORDS = {"likelihood_form", "deviation_space", "ray_correspondence", "table_cache_dir"}
NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


class ParameterFiles(unittest.TestCase):
    def test_rosparam_reads_every_file_as_amcr_does(self):
        import rosparam  # ROS's own reader: what `rosparam load` and <rosparam file> use
        for path in CONFIGS:
            with self.subTest(path=os.path.basename(path)):
                with open(path) as f:
                    text = f.read()
                self.assertFalse(text.startswith("%YAML"), "OpenCV's header makes rosparam refuse the file")
                loaded = rosparam.load_file(path)
                self.assertEqual(len(loaded), 1)
                values, namespace = loaded[0]
                self.assertEqual(namespace, "/")
                self.assertEqual(values, yaml.safe_load(text))
                for key, value in values.items():
                    self.assertRegex(key, r"^[a-z][a-z0-9_]*$")
                    if key == "prototype_priors":
                        self.assertIsInstance(value, dict)
                    elif key in WORDS:
                        self.assertIsInstance(value, str, key)
                    else:
                        # "1e-3" is a string to YAML 1.1 (rosparam): the nodelet would refuse it.
                        self.assertIsInstance(value, (int, float), "%s = %r is not a number to rosparam" % (key, value))

    def test_the_default_file_holds_every_word_parameter(self):
        with open(CONFIGS[0]) as f:
            values = yaml.safe_load(f)
        self.assertTrue(WORDS <= set(values), WORDS - set(values))
        self.assertFalse(any(isinstance(v, str) and NUMBER.match(v) for v in values.values()))


class CatkinLint(unittest.TestCase):
    def test_package_is_clean(self):
        if shutil.which("catkin_lint") is None:
            self.skipTest("catkin_lint is not installed (Debian: catkin-lint; scripts/test installs it)")
        run = subprocess.run(["catkin_lint", "-W1", "--strict", "--offline", "--color", "never", PACKAGE],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        problems = [line for line in run.stdout.splitlines() if line.startswith("amcr:")]
        self.assertEqual(problems, [], run.stdout)
        self.assertEqual(run.returncode, 0, run.stdout)


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(HERE, "bench"))
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_package_files"))
