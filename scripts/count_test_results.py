#!/usr/bin/python3
"""Counts test cases in catkin's JUnit XML results: prints "passed failed skipped" and
the names of failed cases on stderr, each with the last lines of its failure message, so
that the tail of a CI log says why. catkin_test_results sums the totals of nested
<testsuites>/<testsuite> elements, which counts gtest cases twice."""
import pathlib
import sys
import xml.etree.ElementTree as ET

MESSAGE_LINES = 12


def failure_text(case):
    """The last lines of a failed case's message and text: assertions end up there."""
    parts = []
    for element in list(case.iter("failure")) + list(case.iter("error")):
        parts += [element.get("message") or "", element.text or ""]
    lines = [line for line in "\n".join(parts).splitlines() if line.strip()]
    return lines[-MESSAGE_LINES:]


passed = failed = skipped = 0
for path in sorted(pathlib.Path(sys.argv[1]).rglob("*.xml")):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        failed += 1
        print(f"{path.name}: unreadable result file ({e})", file=sys.stderr)
        continue
    cases = list(root.iter("testcase"))
    if not cases and root.get("errors", "0") != "0":
        failed += 1  # e.g. a rostest whose node never started
        print(f"{path.name}: error without test cases", file=sys.stderr)
    for case in cases:
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
            print(f"{path.name}: {case.get('classname')}.{case.get('name')}", file=sys.stderr)
            for line in failure_text(case):
                print(f"    {line[:300]}", file=sys.stderr)
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            skipped += 1
        else:
            passed += 1
print(passed, failed, skipped)
