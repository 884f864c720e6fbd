#!/usr/bin/env python3
"""What scripts/test.sh prints after the suites: the number of skipped tests of each JUnit file
(ctest --output-junit, pytest --junitxml) and, under CI, a failure for any skip that
tests/allowed_skips.txt does not list; then the ten slowest tests of the first file (the
Release suite), so that growth is seen.

usage: test_summary.py ALLOWED_SKIPS LABEL=JUNIT.xml [LABEL=JUNIT.xml ...]"""
import os
import sys
import xml.etree.ElementTree as ElementTree


def test_cases(path):
    """(name, seconds, skip message or None) of every test case of a JUnit file."""
    for case in ElementTree.parse(path).getroot().iter("testcase"):
        name, group = case.get("name"), case.get("classname")
        name = name.split("  # GetParam()")[0]  # ctest's names of parameterised GoogleTest tests
        if group and group.split("  # GetParam()")[0] != name:
            name = f"{group}::{name}"  # pytest: the module, then the test function
        skipped = case.find("skipped")
        message = None if skipped is None else skip_reason(skipped, case.findtext("system-out") or "")
        yield name, float(case.get("time") or 0.0), message


def skip_reason(skipped, output):
    """pytest's reason, or the line GoogleTest prints after 'Skipped' (ctest only says that its
    SKIP_REGULAR_EXPRESSION matched)."""
    message = (skipped.get("message") or skipped.text or "").strip()
    if message == "SKIP_REGULAR_EXPRESSION_MATCHED":
        lines = output.splitlines()
        for line, following in zip(lines, lines[1:]):
            if line.endswith(": Skipped"):
                return following.strip()
    return message.splitlines()[0] if message else ""


def allowed_skips(path):
    """The test names of the allow-list: one a line, '#' starts a comment."""
    with open(path, encoding="utf-8") as lines:
        return {line.split("#")[0].strip() for line in lines} - {""}


def main(argv):
    allowed = allowed_skips(argv[1])
    in_ci = bool(os.environ.get("CI"))
    suites = [argument.split("=", 1) for argument in argv[2:]]
    forbidden = []
    for label, path in suites:
        cases = list(test_cases(path))
        skips = [(name, message) for name, _, message in cases if message is not None]
        print(f"== {label}: {len(cases)} tests, {len(skips)} skipped")
        for name, message in skips:
            print(f"   skipped {name}: {message}")
            if name not in allowed:
                forbidden.append(f"{label}: {name}")
    label, path = suites[0]
    print(f"== the ten slowest tests of the {label}")
    for name, seconds, _ in sorted(test_cases(path), key=lambda case: -case[1])[:10]:
        print(f"  {seconds:7.1f} s  {name}")
    if in_ci and forbidden:
        print("CI: these tests skipped and tests/allowed_skips.txt does not allow it:", *forbidden, sep="\n  ")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
