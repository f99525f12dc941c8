#!/usr/bin/python3
"""Checks the size rules of the C++ (.cpp, .h, .hpp, .cc) in src/, include/, bench/ and test/:
no file over 500 lines (800 in test/), no function and no lambda over 80 lines, no class, struct
or union over 300 lines counting its body and its member functions defined out of line.

The code is read with its comments, string, raw string and character literals and preprocessor
lines blanked out, and its braces are matched. A brace opened at namespace or class level (the
first after `namespace {` or a `public:` label included) whose head ends like a signature
(`...)`, `...) const override`, `...) -> T`, a constructor's initialiser list) opens a function:
its length is from the first line of its signature to its closing brace. A brace after a
lambda's introducer (`[...]`, `[...](...)`, `[...](...) mutable -> T`) opens a lambda wherever it
is (a function, an initialiser list, a table), measured from its `[` to its closing brace. A
brace after a `class`, `struct` or `union` head (not `enum`) opens a class body, measured from
the first line of its head (`template <...>` included) to its closing brace.

A class's size is its body plus every out-of-line definition of its member functions
(`T X::f(...) {...}`, `X::X(...) : ... {...}`, `X::~X`, `X::operator=`), in any file of the four
trees: a function defined at namespace level under a qualified name is attributed to the class
that name's qualification names (`World::Impl::x` to `World::Impl`; a class nested in another
is named by both, `Outer::Inner`; leading namespaces are dropped until a class is named, and
one that names none, such as `detail::f`, is a free function). A name is looked up first among
the classes of the definition's own file, then among those of the headers; a name that several
headers define is resolved to the one named as the definition's file (`x.h` for `x.cpp`), else
left unattributed.
Prints one line per violation and exits 1 if any; with --gtest_output=xml:FILE also writes a
gtest-style result for catkin_test_results.
"""
import os
import re
import sys

from gtest_xml import write_result

MAX_FILE_LINES = {'src': 500, 'include': 500, 'bench': 500, 'test': 800}
MAX_FUNCTION_LINES = 80
MAX_CLASS_LINES = 300
CPP = ('.cpp', '.h', '.hpp', '.cc')
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')

RAW_PREFIX = re.compile(r'(?:^|\W)(?:u8|u|U|L)?R$')
LABELS = re.compile(r'\s*((public|private|protected)\s*:(?!:)\s*)+')
NAMESPACE = re.compile(r'\bnamespace\b|\bextern\s*"\s*"\s*$')
CLASS = re.compile(r'\s*(template\s*<.*>\s*)?(\[\[.*\]\]\s*)?(typedef\s+)?'
                   r'(class|struct|union|enum)\b', re.S)
QUALIFIERS = (r'((const|volatile|mutable|constexpr|consteval|static|noexcept|override|final|'
              r'&&?|throw\s*\(\s*\)|noexcept\s*\(\s*\)|__attribute__\s*\(\s*\)|'
              r'\[\[[^\]]*\]\])\s*)*(->[^;{}]*)?$')
SIGNATURE_END = re.compile(r'\(\s*\)\s*' + QUALIFIERS)
INITIALISER_LIST = re.compile(r'\)\s*(noexcept\s*)?:(?!:)')
LAMBDA_END = re.compile(r'\]\s*(<[^;{}]*>\s*)?(\(\s*\)\s*)?' + QUALIFIERS)
CLASS_NAME = re.compile(r'\s*(template\s*<.*>\s*)?(\[\[.*\]\]\s*)?(typedef\s+)?'
                        r'(class|struct|union)\b\s*(alignas\s*\(\s*\)\s*)?'
                        r'(\[\[[^\]]*\]\]\s*)?(\w+(\s*::\s*\w+)*)?', re.S)
QUALIFICATION = r'(\w+\s*(<[^()<>]*>)?\s*::\s*)*'
NAME = re.compile(r'(' + QUALIFICATION +
                  r'operator\s*(\(\s*\)|\[\s*\]|[^\s\w(][^\s(]*|\w[\w\s:<>*&]*?)|'
                  + QUALIFICATION + r'~?\w+)\s*(<[^()]*>)?\s*$')


def blank(text):
    """`text` with comments, string, raw string and character literals and preprocessor lines
    blanked out (a literal keeps its quotes); newlines are kept, so line numbers are too."""
    out = []
    i, n = 0, len(text)
    line_start = True  # nothing but blanks since the last newline

    def skip(start, end, keep_quotes=False):
        gap = re.sub(r'[^\n]', ' ', text[start:end])
        if keep_quotes:  # "..." and '...' stay "  " and '  ' (extern "C" is told by them)
            gap = text[start] + gap[1:]
            if end - start >= 2 and text[end - 1] == text[start]:
                gap = gap[:-1] + text[start]
        out.append(gap)
        return end

    while i < n:
        c = text[i]
        if c == '\n':
            out.append(c)
            i += 1
            line_start = True
            continue
        if line_start and c == '#':  # a preprocessor line, continued by a trailing backslash
            end = i
            while True:
                end = text.find('\n', end)
                if end < 0:
                    end = n
                    break
                if text[end - 1] != '\\':
                    break
                end += 1
            i = skip(i, end)
            continue
        if not c.isspace():
            line_start = False
        if text.startswith('//', i):
            end = text.find('\n', i)
            i = skip(i, n if end < 0 else end)
        elif text.startswith('/*', i):
            end = text.find('*/', i + 2)
            i = skip(i, n if end < 0 else end + 2)
        elif c == '"' and RAW_PREFIX.search(text[max(0, i - 4):i]):
            open_paren = text.find('(', i)
            delimiter = ')' + text[i + 1:open_paren] + '"'
            end = text.find(delimiter, open_paren)
            i = skip(i, n if open_paren < 0 or end < 0 else end + len(delimiter), True)
        elif c == '"' or (c == "'" and not re.search(r'(?<![\w])\d\w*$', text[max(0, i - 40):i])):
            end = i + 1  # a string or a character literal (not a digit separator as in 1'000)
            while end < n and text[end] not in (c, '\n'):
                end += 2 if text[end] == '\\' else 1
            i = skip(i, min(end + 1 if end < n and text[end] == c else end, n), True)
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def empty_parens(head):
    """`head` with the inside of every balanced (...) blanked; an unclosed `(` (a call a lambda is
    passed to) keeps what follows it. Positions are kept."""
    chars = list(head)
    opened = []
    for i, c in enumerate(chars):
        if c == '(':
            opened.append(i)
        elif c == ')' and opened:
            start = opened.pop()
            chars[start + 1:i] = ' ' * (i - start - 1)
    return ''.join(chars)


def lambda_start(flat):
    """The index of the `[` of the lambda introducer `flat` (a head, parens emptied) ends with,
    or None: a `[...]` after an identifier (other than return) is a subscript or an array."""
    close = flat.rfind(']')
    if close < 0 or not LAMBDA_END.match(flat, close):
        return None
    depth = 0
    for i in range(close, -1, -1):
        depth += {']': 1, '[': -1}.get(flat[i], 0)
        if depth == 0:
            break
    else:
        return None
    before = flat[:i].rstrip()
    word = re.search(r'\w+$', before)
    if before.endswith((']', ')')) or (word and word.group() != 'return') or \
            re.search(r'operator\s*$', before):
        return None
    return i


def function_name(head, flat):
    """The name of the function whose head (parens emptied: `flat`) opens a body, or None."""
    init = INITIALISER_LIST.search(flat)
    end = SIGNATURE_END.search(flat)
    if init and re.search(r'(\(\s*\)|\{\})\s*$', flat):  # Foo() : a_(x), b_{y} {
        params = flat.rfind('(', 0, init.start())
    elif end:
        params = end.start()
    else:
        return None
    name = NAME.search(flat, 0, params)
    if not name:
        return '?'
    if re.fullmatch(r'[A-Z][A-Z0-9_]*', name.group(1)):  # TEST(Suite, Name) and the like
        close = flat.find(')', params)
        return name.group(1) + re.sub(r'\s+', ' ', head[params:close + 1])
    return name.group(1).strip()


def classify(head, lines, in_scope):
    """What a `{` after `head` opens: (kind, name, first line). Kinds: 'scope' (a namespace, an
    enum), 'class' (a class, struct or union), 'function', 'lambda', 'init' (an initialiser at
    scope level) or 'block'."""
    labels = LABELS.match(head) if in_scope else None
    start = labels.end() if labels else 0
    head = head[start:]
    flat = empty_parens(head)
    text_start = len(head) - len(head.lstrip())
    first = lines[start + text_start] if text_start < len(head) else None
    bracket = lambda_start(flat)
    if bracket is not None:
        return 'lambda', None, lines[start + bracket]
    if in_scope and NAMESPACE.search(flat):
        return 'scope', None, first
    if in_scope:
        name = function_name(head, flat)
        if name:
            return 'function', name, first
    if CLASS.match(flat):
        named = CLASS_NAME.match(flat)
        if named:
            return 'class', re.sub(r'\s+', '', named.group(7) or '?'), first
        return 'scope', None, first
    return ('init' if in_scope else 'block'), None, first


def functions(lines):
    """Yields (what, first line, last line) of every function ('function NAME') and lambda
    ('lambda' or 'lambda in NAME') body in the file of `lines`."""
    for what, first, last in bodies(lines):
        if not what.startswith('class '):
            yield what, first, last


def classes(lines):
    """Yields (what, first line, last line) of every class, struct and union body ('class
    NAME') in the file of `lines`."""
    for what, first, last in bodies(lines):
        if what.startswith('class '):
            yield what, first, last


def bodies(lines):
    """Yields (what, first line, last line) of every function, lambda and class body in the
    file of `lines`, each as it closes."""
    for what, first, last, _ in definitions(lines):
        yield what, first, last


def owner(name):
    """The qualification of the function name `name` without template arguments and blanks
    (`Foo<T>::Bar::f` -> `Foo::Bar`, `X::operator<` -> `X`), or None if it has none."""
    cut = name.find('operator')
    prefix = name[:cut] if cut >= 0 else name[:name.rfind('::') + 2] if '::' in name else ''
    prefix = re.sub(r'\s+', '', prefix)
    while re.search(r'<[^<>]*>', prefix):
        prefix = re.sub(r'<[^<>]*>', '', prefix)
    prefix = prefix.strip(':')
    return prefix or None


def definitions(lines):
    """Yields (what, first line, last line, qualified name) of every function, lambda and class
    body in the file of `lines`, each as it closes. A class's qualified name is its name after
    those of the classes it is nested in (`Outer::Inner`); a function's is the qualification of
    its name (`World::Impl` for `World::Impl::x`) if it is defined at namespace level (an
    out-of-line member's), else None; a lambda's is None."""
    text = blank('\n'.join(lines))
    head, head_lines = [], []
    frames = []  # per open brace: (kind, name, first line, its line, the head before it)
    number = 1
    for c in text:
        if c == '{':
            in_scope = not frames or frames[-1][0] in ('scope', 'class')
            kind, name, first = classify(''.join(head), head_lines, in_scope)
            frames.append((kind, name, first or number, number, head, head_lines))
            head, head_lines = [], []
        elif c == '}' and frames:
            kind, name, first, opened, head, head_lines = frames.pop()
            if kind == 'function':
                in_class = any(f[0] == 'class' for f in frames)
                yield f'function {name}', first, number, None if in_class else owner(name)
            elif kind == 'class':
                outer = [f[1] for f in frames if f[0] == 'class']
                yield f'class {name}', first, number, '::'.join(outer + [name])
            elif kind == 'lambda':
                outer = [f[1] for f in frames if f[0] == 'function']
                yield ('lambda in ' + outer[-1] if outer else 'lambda'), first, number, None
            if kind in ('lambda', 'init'):  # the statement goes on: `= [] {...};`, `a_{x}, b_(y)`
                head, head_lines = head + ['{', '}'], head_lines + [opened, number]
            else:
                head, head_lines = [], []
        elif c == ';':
            head, head_lines = [], []
        else:
            head.append(c)
            head_lines.append(number)
        if c == '\n':
            number += 1


HEADER = ('.h', '.hpp')


def resolve(name, rel, bodies_by_name):
    """The class body (rel, first line, ...) the qualification `name` of a function defined in
    the file `rel` names, or None: leading namespaces are dropped until a class is named; one
    in `rel` itself first, else the only header's, else the header named as `rel` (x.h, x.cpp)."""
    parts = name.split('::')
    for i in range(len(parts)):
        found = bodies_by_name.get('::'.join(parts[i:]), [])
        own = [b for b in found if b[0] == rel]
        if own:
            return own[0]
        headers = [b for b in found if b[0].endswith(HEADER)]
        if len(headers) > 1:
            stem = os.path.splitext(os.path.basename(rel))[0]
            headers = [b for b in headers if os.path.splitext(os.path.basename(b[0]))[0] == stem]
        if len(headers) == 1:
            return headers[0]
        if found:
            return None
    return None


def class_problems(files):
    """The classes over MAX_CLASS_LINES in `files` ({rel: lines}), each counted as its body
    plus the out-of-line definitions of its member functions in any of `files`."""
    bodies_by_name = {}  # qualified name -> [(rel, first, last, [(rel, lines) of members])]
    members = []  # (rel, qualification, lines) of every function defined at namespace level
    for rel, lines in files.items():
        for what, first, last, name in definitions(lines):
            if what.startswith('class '):
                bodies_by_name.setdefault(name, []).append((rel, first, last, []))
            elif name:
                members.append((rel, name, last - first + 1))
    for rel, name, length in members:
        body = resolve(name, rel, bodies_by_name)
        if body:
            body[3].append((rel, length))
    problems = []
    for name, found in bodies_by_name.items():
        for rel, first, last, outside in found:
            own = last - first + 1
            total = own + sum(length for _, length in outside)
            if total <= MAX_CLASS_LINES:
                continue
            what = f'{rel}:{first}: class {name} has {total} lines (at most {MAX_CLASS_LINES})'
            if not outside:
                problems.append((rel, first, what))
                continue
            where = {}
            for member_rel, length in outside:
                count, lines = where.get(member_rel, (0, 0))
                where[member_rel] = (count + 1, lines + length)
            spread = ', '.join(f'{lines} in {member_rel} ({count} functions)'
                               for member_rel, (count, lines) in sorted(where.items()))
            problems.append((rel, first, f'{what} counting its out-of-line members: its body '
                                         f'{own}, its member functions {spread}'))
    return [what for _, _, what in sorted(problems)]


def file_problems(rel, lines, max_file_lines):
    """The violations in the file `rel` of `lines`, which may have `max_file_lines`, alone:
    its classes counted with the member functions it defines out of line itself."""
    return own_problems(rel, lines, max_file_lines) + class_problems({rel: lines})


def own_problems(rel, lines, max_file_lines):
    """The file's length and its functions' and lambdas' over their limits."""
    problems = []
    if len(lines) > max_file_lines:
        problems.append(f'{rel}: {len(lines)} lines (at most {max_file_lines})')
    for what, first, last in functions(lines):
        if last - first + 1 > MAX_FUNCTION_LINES:
            problems.append(f'{rel}:{first}: {what} has {last - first + 1} lines '
                            f'(at most {MAX_FUNCTION_LINES})')
    return problems


def check(root):
    problems = []
    files = {}
    for tree, max_file_lines in MAX_FILE_LINES.items():
        for folder, dirs, names in os.walk(os.path.join(root, tree)):
            dirs.sort()
            for f in sorted(names):
                if f.endswith(CPP):
                    path = os.path.join(folder, f)
                    with open(path, encoding='utf-8') as source:
                        lines = source.read().splitlines()
                    rel = os.path.relpath(path, root)
                    files[rel] = lines
                    problems += own_problems(rel, lines, max_file_lines)
    return problems + class_problems(files)


def main():
    problems = check(ROOT)
    for p in problems:
        print(p)
    write_result(sys.argv[1:], 'CodeSize', 'FilesAndFunctionsWithinLimits', problems)
    print(f'code_size: {len(problems)} problem(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
