#!/usr/bin/python3
"""Sums gtest/rostest JUnit XML result files: prints one line per failed test (file, suite and
name) with the first lines of its failure message, with --slowest N the N slowest tests and
their times, then 'N passed, N failed[, N skipped]'. Exit 0 only when at least one test ran and
none failed.
    count_results.py [--slowest N] FILE.xml..."""
import os
import sys
import xml.etree.ElementTree as ET

MESSAGE_LINES = 6

args = sys.argv[1:]
slowest = 0
if args[:1] == ["--slowest"]:
    slowest = int(args[1])
    args = args[2:]

passed = failed = skipped = 0
timed = []
for path in args:
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as err:
        print(f"{path}: unreadable result file ({err})")
        failed += 1
        continue
    for case in root.iter("testcase"):
        try:
            timed.append((float(case.get("time") or 0.0),
                          f"{os.path.basename(path)}: {case.get('classname')}.{case.get('name')}"))
        except ValueError:
            pass
        problems = case.findall("failure") + case.findall("error")
        if problems:
            failed += 1
            print(f"FAILED: {os.path.basename(path)}: {case.get('classname')}.{case.get('name')}")
            for problem in problems:
                text = (problem.get("message") or problem.text or "").strip()
                for line in text.splitlines()[:MESSAGE_LINES]:
                    print(f"    {line}")
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            skipped += 1
        else:
            passed += 1
if slowest > 0 and timed:
    print(f"slowest {min(slowest, len(timed))} tests:")
    for seconds, name in sorted(timed, reverse=True)[:slowest]:
        print(f"  {seconds:7.1f} s  {name}")
line = f"{passed} passed, {failed} failed"
if skipped:
    line += f", {skipped} skipped"
print(line)
sys.exit(0 if passed > 0 and failed == 0 else 1)
