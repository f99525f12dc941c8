"""A one-test gtest-style XML result, which catkin_test_results counts: a failure per problem."""
import os
from xml.sax.saxutils import escape


def write_result(args, suite, case, problems):
    """Writes the result to FILE if `args` holds --gtest_output=xml:FILE."""
    out = [a.split('xml:', 1)[1] for a in args if a.startswith('--gtest_output=xml:')]
    if not out:
        return
    body = ''.join(f'<failure message="{escape(p, {chr(34): "&quot;"})}"/>' for p in problems)
    os.makedirs(os.path.dirname(out[0]), exist_ok=True)
    with open(out[0], 'w') as f:
        f.write(f'<?xml version="1.0"?>\n<testsuites><testsuite name="{suite}" tests="1" '
                f'failures="{1 if problems else 0}"><testcase name="{case}" classname="{suite}">'
                f'{body}</testcase></testsuite></testsuites>\n')


def run_unittests(args, suite, case):
    """Runs the calling module's unittest cases (argv: the program name only), writes their
    failures as one gtest-style result if `args` asks for it, and exits 1 if any failed."""
    import sys
    import unittest
    result = unittest.main(argv=args[:1], exit=False, verbosity=2).result
    problems = [f"{test.id()}: {trace.strip().splitlines()[-1]}"
                for test, trace in result.failures + result.errors]
    write_result(args, suite, case, problems)
    sys.exit(1 if problems else 0)
