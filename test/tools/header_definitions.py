#!/usr/bin/python3
"""Every function a public header declares is defined by the package's libraries.

Reads the declarations (a name followed by a parameter list, ending in ';', outside any
function body, not inline, defaulted, deleted or pure) of include/flapsim/*.h and
include/flapsim_ros/*.h, and looks each name up among the functions the libraries given on
the command line define (`nm -C --defined-only`). Prints one line per declaration no library
defines and exits 1 if any; --gtest_output=xml:FILE writes a gtest-style result.

usage: header_definitions.py LIB [LIB ...] [--gtest_output=xml:FILE]
"""
import os
import re
import subprocess
import sys

from gtest_xml import write_result

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
HEADER_DIRS = ['include/flapsim', 'include/flapsim_ros']
NOT_NAMES = {'if', 'for', 'while', 'switch', 'return', 'sizeof', 'static_assert', 'decltype',
             'operator', 'alignas', 'noexcept', 'explicit', 'defined'}


def code(text):
    text = re.sub(r'/\*.*?\*/', ' ', text, flags=re.S)
    text = re.sub(r'//[^\n]*', ' ', text)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    return re.sub(r'^\s*#[^\n]*', ' ', text, flags=re.M)


def declarations(text):
    """Yields (name, statement) of the function declarations at namespace or class level."""
    text = code(text)
    depth_kinds = []  # per open brace: True if a function body (or initialiser) is inside
    statement = ''
    for ch in text:
        if ch == '{':
            head = statement.strip()
            body = bool(re.search(r'\)\s*(const|override|final|noexcept|\s)*$', head)) or \
                bool(re.search(r'\)\s*:', head)) or '=' in head or \
                any(depth_kinds)
            depth_kinds.append(body)
            statement = ''
        elif ch == '}':
            if depth_kinds:
                depth_kinds.pop()
            statement = ''
        elif ch == ';':
            if not any(depth_kinds):
                yield statement.strip()
            statement = ''
        else:
            statement += ch


def declared_functions(path):
    names = []
    for st in declarations(open(path, encoding='utf-8').read()):
        st = ' '.join(st.split())
        if re.search(r'\b(inline|constexpr|typedef|using|friend|template)\b', st):
            continue
        if re.search(r'=\s*(default|delete|0)\s*$', st) or 'operator' in st:
            continue
        m = re.match(r'^(?:public:|private:|protected:|\s)*(?:[\w:<>,\*&\s]+?\s+[\*&]*)?~?(\w+)\s*\(', st)
        if not m or m.group(1) in NOT_NAMES:
            continue
        # A member initialised in its declaration (`Type name = Type(...)`), or a variable
        # constructed with arguments, is not a function declaration.
        if re.match(r'^[\w:<>,\s]+\s+\w+\s*=', st):
            continue
        names.append((m.group(1), st))
    return names


def defined_names(libs):
    names = set()
    for lib in libs:
        out = subprocess.run(['nm', '-C', '--defined-only', lib], capture_output=True,
                             text=True, check=True).stdout
        for line in out.split('\n'):
            parts = line.split(' ', 2)
            if len(parts) < 3 or parts[1] not in 'TtWw':
                continue
            for n in re.findall(r'([~\w]+)\(', parts[2].replace('[abi:cxx11]', '')):
                names.add(n)
    return names


def main():
    libs = [a for a in sys.argv[1:] if not a.startswith('--')]
    defined = defined_names(libs)
    problems = []
    checked = 0
    for d in HEADER_DIRS:
        folder = os.path.join(ROOT, d)
        for f in sorted(os.listdir(folder)):
            if not f.endswith('.h'):
                continue
            for name, st in declared_functions(os.path.join(folder, f)):
                checked += 1
                if name not in defined:
                    problems.append(f'{d}/{f}: {name} is declared ({st[:90]}) but no library '
                                    'defines it')
    for p in problems:
        print(p)
    print(f'header_definitions: {checked} declarations, {len(problems)} undefined')
    write_result(sys.argv[1:], 'PublicHeaders', 'EveryDeclaredFunctionIsDefined', problems)
    return 1 if problems or checked == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
