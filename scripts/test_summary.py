#!/usr/bin/env python3
"""Counts the test cases in catkin's JUnit results and prints 'N passed, N failed, N skipped'.

Usage: test_summary.py RESULTS_DIR [TARGETS_FILE]
TARGETS_FILE lists catkin's run_tests targets (`make help` of the build folder, one a line): each leaf
target (run_tests_<package>_<gtest|rostest|fuzz>_<name>) must have left its result file
(<package>/<type>-<name>.xml); a missing one is counted as a failure (the test did not run).
A failed case is listed with the end of its failure message (the reason, for CI logs that show
only the tail). Each test case is counted once: a rostest's summary ('rostest-*.xml') holds one case per test
node, whose own cases are in 'rosunit-<name>.xml'; those are counted (and the summary's failure
when the node died before writing them). An unreadable result file counts as a failure. Exits 1
when anything failed or nothing ran.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def cases(path):
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == 'testsuite' else root.iter('testsuite')
    for suite in suites:
        # rosunit writes no <skipped/>: a Python rostest that skips prints 'SKIPPED <test name>: why'.
        out = suite.find('system-out')
        printed = (out.text or '') if out is not None else ''
        for case in suite.iter('testcase'):
            name = '%s.%s' % (case.get('classname', suite.get('name', '?')), case.get('name', '?'))
            bad = case.find('failure')
            if bad is None:
                bad = case.find('error')
            if bad is not None:
                why = (bad.get('message') or '') + ' ' + (bad.text or '')
                yield name, 'failed: ' + ' '.join(why.split())[-500:]
            elif (case.find('skipped') is not None or case.get('status') == 'notrun' or
                  'SKIPPED %s:' % case.get('name', '?') in printed):
                yield name, 'skipped'
            else:
                yield name, 'passed'


def expected_files(results, targets_file):
    """The result files the leaf run_tests targets of the packages in RESULTS_DIR's build write."""
    packages = sorted(os.listdir(os.path.join(results, '..', '..', 'src')) if os.path.isdir(
        os.path.join(results, '..', '..', 'src')) else os.listdir(results), key=len, reverse=True)
    out = []
    with open(targets_file) as f:
        for line in f:
            target = line.strip()
            for pkg in packages:
                prefix = 'run_tests_%s_' % pkg
                if not target.startswith(prefix):
                    continue
                kind, _, name = target[len(prefix):].partition('_')
                if kind in ('gtest', 'rostest', 'fuzz') and name:
                    if kind == 'rostest' and name.endswith('.test'):
                        name = name[:-len('.test')]
                    out.append(os.path.join(results, pkg, '%s-%s.xml' % (kind, name)))
                break
    return out


def main():
    results = sys.argv[1]
    counts = {'passed': 0, 'failed': 0, 'skipped': 0}
    failures = []
    if len(sys.argv) > 2:
        for path in expected_files(results, sys.argv[2]):
            if not os.path.exists(path):
                counts['failed'] += 1
                failures.append('%s: no result file (the test did not run)' % os.path.relpath(path, results))

    def count(path, statuses):
        for name, status in statuses:
            status, _, why = status.partition(': ')
            counts[status] += 1
            if status == 'failed':
                failures.append('%s (%s)%s' % (name, os.path.relpath(path, results), ': ' + why if why else ''))

    files = sorted(glob.glob(os.path.join(results, '**', '*.xml'), recursive=True))
    for f in files:
        base = os.path.basename(f)
        if base.startswith('rosunit-'):
            continue  # read through its rostest summary below
        try:
            cases_here = list(cases(f))
        except (ET.ParseError, OSError) as e:
            counts['failed'] += 1
            failures.append('%s: unreadable result file (%s)' % (os.path.relpath(f, results), e))
            continue
        if not base.startswith('rostest-'):
            count(f, cases_here)
            continue
        # A rostest summary holds one case 'test<name>' per test node; the node's own cases are in
        # rosunit-<name>.xml next to it. Count those, and the summary's failure if they show none.
        for name, status in cases_here:
            test_name = name.split('.')[-1][len('test'):]
            detail = os.path.join(os.path.dirname(f), 'rosunit-%s.xml' % test_name)
            try:
                detailed = list(cases(detail)) if os.path.exists(detail) else []
            except (ET.ParseError, OSError):
                detailed = []
            if not detailed:
                count(f, [(name, status)])
                continue
            count(detail, detailed)
            if status.startswith('failed') and not any(st.startswith('failed') for _, st in detailed):
                count(f, [(name, 'failed')])
    for name in failures:
        print('FAILED: ' + name)
    total = sum(counts.values())
    print('%d passed, %d failed, %d skipped' % (counts['passed'], counts['failed'], counts['skipped']))
    return 1 if counts['failed'] or total == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
