#!/usr/bin/python3
"""Counts the test cases in the gtest/rostest XML files under a directory.

usage: test_summary.py RESULTS_DIR EXIT_CODE [STAGE]
       test_summary.py --count RESULTS_DIR      (prints only the number of test cases)
       test_summary.py --record-failure RESULTS_DIR NAME MESSAGE
           (writes RESULTS_DIR/NAME.failure.xml, one failed test case NAME, unless
           RESULTS_DIR/NAME.xml already holds a failure: a run that failed without a word in its
           own XML, a sanitizer report, a fuzzer crash)

Prints the failing test cases, then as its last line `N passed, N failed` (with `, N skipped`
when some were skipped). Each <testcase> counts once (catkin_test_results double-counts gtest
1.12 files, which carry totals on both <testsuites> and <testsuite>): failed when it has a
<failure> or <error>, skipped when it has <skipped> or was not run, passed otherwise. A file
that does not parse counts as one failure. When EXIT_CODE is not 0 but no test case failed (the
build failed, or no test ran), the failed stage is counted as one failure, so that the summary
never reads as a success when the command failed.
"""

import os
import sys
import xml.etree.ElementTree as ET


def has_failure(path):
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        return False
    return any(case.findall("failure") or case.findall("error") for case in root.iter("testcase"))


def record_failure(results_dir, name, message):
    if has_failure(os.path.join(results_dir, name + ".xml")):
        return
    os.makedirs(results_dir, exist_ok=True)
    suites = ET.Element("testsuites")
    suite = ET.SubElement(suites, "testsuite", name=name, tests="1", failures="1")
    case = ET.SubElement(suite, "testcase", classname=name, name="run")
    ET.SubElement(case, "failure", message=message[:2000]).text = message
    ET.ElementTree(suites).write(os.path.join(results_dir, name + ".failure.xml"), encoding="utf-8",
                                 xml_declaration=True)


def main():
    if sys.argv[1] == "--record-failure":
        record_failure(sys.argv[2], sys.argv[3], sys.argv[4])
        return
    count_only = sys.argv[1] == "--count"
    if count_only:
        sys.argv.pop(1)
        sys.argv[2:] = ["0"]
    results_dir = sys.argv[1]
    exit_code = int(sys.argv[2])
    stage = sys.argv[3] if len(sys.argv) > 3 else ""
    passed = failed = skipped = 0
    failures = []
    files = []
    if os.path.isdir(results_dir):
        for root, _, names in os.walk(results_dir):
            files += [os.path.join(root, n) for n in names if n.endswith(".xml")]
    for path in sorted(files):
        try:
            tree = ET.parse(path)
        except (ET.ParseError, OSError) as error:
            failed += 1
            failures.append("%s: unreadable result file (%s)" % (os.path.relpath(path, results_dir), error))
            continue
        for case in tree.getroot().iter("testcase"):
            name = "%s.%s" % (case.get("classname", "?"), case.get("name", "?"))
            problems = case.findall("failure") + case.findall("error")
            if problems:
                failed += 1
                message = (problems[0].get("message") or problems[0].text or "").strip()
                summary = " | ".join(l.strip() for l in message.splitlines()[:3] if l.strip())
                failures.append("%s: %s" % (name, summary[:300] or "failed"))
            elif (case.find("skipped") is not None or case.get("status") == "notrun"
                  or case.get("result") in ("skipped", "suppressed")):
                skipped += 1
            else:
                passed += 1
    if count_only:
        print(passed + failed + skipped)
        return
    for line in failures:
        print("FAILED " + line)
    if exit_code != 0 and failed == 0:
        failed = 1
        if passed + skipped == 0:
            print("no test ran%s" % (" (failed at stage: %s)" % stage if stage else ""))
        else:
            print("the run failed%s; counted as one failure"
                  % (" at stage: %s" % stage if stage else ""))
    summary = "%d passed, %d failed" % (passed, failed)
    if skipped:
        summary += ", %d skipped" % skipped
    print(summary)


if __name__ == "__main__":
    main()
