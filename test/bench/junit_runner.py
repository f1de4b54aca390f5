"""Runs a module's unittest cases verbosely and, with --xml PATH, writes a JUnit file catkin reads."""
import os
import sys
import time
import unittest


def junit(result, path, seconds, name):
    cases = result.testsRun
    with open(path, "w") as f:
        f.write('<?xml version="1.0" encoding="UTF-8"?>\n<testsuite name="%s" tests="%d" '
                'failures="%d" errors="%d" skipped="%d" time="%.2f">\n' % (
                    name, cases, len(result.failures), len(result.errors), len(result.skipped), seconds))
        bad = {t.id(): m for t, m in result.failures + result.errors}
        skipped = {t.id(): m for t, m in result.skipped}
        for test in result.all:
            name = test.id().split(".")
            f.write('  <testcase classname="%s" name="%s">' % (name[-2], name[-1]))
            if test.id() in bad:
                f.write('<failure message="failed"><![CDATA[%s]]></failure>' % bad[test.id()])
            elif test.id() in skipped:
                f.write('<skipped message="%s"/>' % skipped[test.id()].replace('"', "'"))
            f.write("</testcase>\n")
        f.write("</testsuite>\n")


class Recording(unittest.TextTestResult):
    def startTest(self, test):
        self.all = getattr(self, "all", [])
        self.all.append(test)
        super().startTest(test)



def run_module(module, name):
    """Runs the cases of `module`; returns the exit status (0: all passed)."""
    xml = sys.argv[sys.argv.index("--xml") + 1] if "--xml" in sys.argv else None
    suite = unittest.defaultTestLoader.loadTestsFromModule(module)
    start = time.time()
    result = unittest.TextTestRunner(resultclass=Recording, verbosity=2).run(suite)
    if xml:
        os.makedirs(os.path.dirname(os.path.abspath(xml)), exist_ok=True)
        junit(result, xml, time.time() - start, name)
    return 0 if result.wasSuccessful() else 1
