#!/usr/bin/env python3
"""Counts the test cases in catkin's JUnit results and prints 'N passed, N failed, N skipped'.

Usage: test_summary.py RESULTS_DIR [EXPECTED_FILES]
Each test executable's own results are counted once: a rostest writes its gtest's XML inside a
'rostest-*.xml' summary, so only that summary's cases are read for it. A result file that is
missing or unreadable counts as a failure. Exits 1 when anything failed or nothing ran.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def cases(path):
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == 'testsuite' else root.iter('testsuite')
    for suite in suites:
        for case in suite.iter('testcase'):
            name = '%s.%s' % (case.get('classname', suite.get('name', '?')), case.get('name', '?'))
            if case.find('failure') is not None or case.find('error') is not None:
                yield name, 'failed'
            elif case.find('skipped') is not None or case.get('status') == 'notrun':
                yield name, 'skipped'
            else:
                yield name, 'passed'


def main():
    results = sys.argv[1]
    counts = {'passed': 0, 'failed': 0, 'skipped': 0}
    failures = []
    files = sorted(glob.glob(os.path.join(results, '**', '*.xml'), recursive=True))
    rostest_dirs = {os.path.dirname(f) for f in files if os.path.basename(f).startswith('rostest-')}
    for f in files:
        base = os.path.basename(f)
        # Inside a package that has rostests, the rostest summary already holds each rostest's cases;
        # its per-node files are named after the test node (rosunit-*), not gtest-*.
        if base.startswith('rosunit-') and os.path.dirname(f) in rostest_dirs:
            continue
        try:
            for name, status in cases(f):
                counts[status] += 1
                if status == 'failed':
                    failures.append('%s (%s)' % (name, os.path.relpath(f, results)))
        except (ET.ParseError, OSError) as e:
            counts['failed'] += 1
            failures.append('%s: unreadable result file (%s)' % (os.path.relpath(f, results), e))
    for name in failures:
        print('FAILED: ' + name)
    total = sum(counts.values())
    print('%d passed, %d failed, %d skipped' % (counts['passed'], counts['failed'], counts['skipped']))
    return 1 if counts['failed'] or total == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
