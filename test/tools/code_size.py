#!/usr/bin/python3
"""Checks the size rules of src/: no file over 500 lines, no function over 80 lines.

A function is a brace block opened at namespace or class level by a line that ends a
signature (`...) {`, `...) const {`, a constructor's initialiser list, ...); its length is
from that line to its closing brace. Prints one line per violation and exits 1 if any;
with --gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import os
import re
import sys

from gtest_xml import write_result

MAX_FILE_LINES = 500
MAX_FUNCTION_LINES = 80
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')


def strip(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)  # strings
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)  # characters
    return line.split('//')[0]


def functions(lines):
    """Yields (name, first line, last line) of every function body at namespace/class level."""
    depth = 0
    scopes = []  # per open brace: 'ns' (namespace, class, struct, enum, extern) or 'fn'
    start = None
    signature = ''
    for number, raw in enumerate(lines, 1):
        line = strip(raw)
        stripped = line.strip()
        for ch in line:
            if ch == '{':
                inside_function = 'fn' in scopes
                if not inside_function:
                    head = (signature + ' ' + stripped).strip()
                    if re.search(r'\b(namespace|class|struct|enum|union)\b[^()]*\{', head) or \
                            re.search(r'extern\s+"', raw) or head.rstrip().endswith('= {') or \
                            re.search(r'=\s*\{', head) or not re.search(r'\)', head):
                        scopes.append('ns')
                    else:
                        scopes.append('fn')
                        name = [n for n in re.findall(r'([~\w:]+)\s*\(', head) if n != '__attribute__']
                        start = (name[0] if name else '?', number)
                else:
                    scopes.append('in')
            elif ch == '}':
                if not scopes:
                    continue
                kind = scopes.pop()
                if kind == 'fn' and start is not None:
                    yield start[0], start[1], number
                    start = None
        if 'fn' not in scopes:
            if stripped.endswith(';') or stripped.endswith('}') or stripped.startswith('#') or \
                    stripped == '':
                signature = ''
            else:
                signature = (signature + ' ' + stripped)[-400:]


def check(root):
    problems = []
    for folder, _, files in os.walk(os.path.join(root, 'src')):
        for f in sorted(files):
            if not f.endswith(('.cpp', '.h')):
                continue
            path = os.path.join(folder, f)
            rel = os.path.relpath(path, root)
            lines = open(path, encoding='utf-8').read().split('\n')
            if len(lines) - 1 > MAX_FILE_LINES:
                problems.append(f'{rel}: {len(lines) - 1} lines (at most {MAX_FILE_LINES})')
            for name, first, last in functions(lines):
                if last - first + 1 > MAX_FUNCTION_LINES:
                    problems.append(f'{rel}:{first}: function {name} has {last - first + 1} lines '
                                    f'(at most {MAX_FUNCTION_LINES})')
    return problems


def main():
    problems = check(ROOT)
    for p in problems:
        print(p)
    write_result(sys.argv[1:], 'CodeSize', 'FilesAndFunctionsWithinLimits', problems)
    print(f'code_size: {len(problems)} problem(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
