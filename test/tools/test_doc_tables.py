#!/usr/bin/python3
"""Every measured table of the docs is written by its script (issue 42, item 6): each table
registered in scripts/doc_tables_registry.py has its block in its doc (between
`<!-- table NAME -->` and `<!-- /table NAME -->`) and its stored raw output
(doc/tables/NAME.txt), and the block is exactly what scripts/doc_tables.py formats from that
output (a figure edited by hand, or one no script writes, differs); every markdown table of
README.md and doc/*.md is in such a block or marked `<!-- table reference -->` on the line right
above it (definitions and defaults, not measurements). Two lists below name, each with why,
the measured tables no script writes yet and the registered ones not yet run; they are not
reported, and an entry that is no longer true is. The finder has its own cases below.
With --gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import glob
import os
import re
import sys
import unittest

from gtest_xml import run_unittests

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import doc_tables  # noqa: E402

REFERENCE = "<!-- table reference -->"
# Measured tables no script writes yet, each with why: (doc, the table's header row) -> reason.
# A ratchet: a table here is not reported, a new unscripted table is, and an entry whose
# table is gone, or now written or marked, fails until it is taken off this list.
NOT_YET_SCRIPTED = {
}
MARKER = re.compile(r"^<!-- (/?)table ([A-Za-z0-9_-]+) -->$")
FENCE = re.compile(r"^\s*(```|~~~)")
SEPARATOR = re.compile(r"^\s*\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?\s*$")

# Registered tables whose commands have not been run yet, each with why: name -> reason. Their
# blocks still hold the figures measured by hand before; a ratchet as NOT_YET_SCRIPTED.
NOT_YET_MEASURED = {
}


def markdown_tables(text):
    """Line numbers (1-based) of the header row of every markdown table outside fenced code: a
    line with a '|' followed by a separator row."""
    lines = text.split("\n")
    fenced = False
    found = []
    for i, line in enumerate(lines):
        if FENCE.match(line):
            fenced = not fenced
        elif (not fenced and "|" in line and i + 1 < len(lines) and SEPARATOR.match(lines[i + 1])
              and not (i > 0 and "|" in lines[i - 1] and lines[i - 1].strip())):
            found.append(i + 1)
    return found


def blocks(text, source):
    """{name: (first line, last line)} of the generated blocks, and the problems of their
    markers (unclosed, nested, closed without opening, twice)."""
    spans = {}
    problems = []
    open_name = None
    for number, line in enumerate(text.split("\n"), 1):
        match = MARKER.match(line.strip())
        if not match or match.group(2) == "reference":
            continue
        closing, name = match.group(1) == "/", match.group(2)
        if not closing:
            if open_name:
                problems.append(f"{source}:{number}: table {name} opens inside table {open_name}")
            open_name, start = name, number
        elif name != open_name:
            problems.append(f"{source}:{number}: '/table {name}' closes no open table {name}")
        else:
            if name in spans:
                problems.append(f"{source}:{number}: table {name} has two blocks")
            spans[name] = (start, number)
            open_name = None
    if open_name:
        problems.append(f"{source}: table {open_name} is never closed")
    return spans, problems


def check(docs, tables, raws, not_yet=(), not_measured=()):
    """The problems of `docs` ({path: text}) against the registry `tables` ({name: Table}) and
    the stored outputs `raws` ({name: Raw, or the text of why it could not be read});
    `not_yet`: the (doc, header row) of tables no script writes yet, `not_measured`: the names
    of registered tables not yet run, neither reported."""
    problems = []
    where = {}
    seen = set()
    for path, text in sorted(docs.items()):
        spans, marker_problems = blocks(text, path)
        problems += marker_problems
        lines = text.split("\n")
        for number in markdown_tables(text):
            inside = any(a < number < b for a, b in spans.values())
            marked = number > 1 and lines[number - 2].strip() == REFERENCE
            if (path, lines[number - 1]) in not_yet and not inside and not marked:
                seen.add((path, lines[number - 1]))
                continue
            if not inside and not marked:
                problems.append(f"{path}:{number}: a table neither written by "
                                f"scripts/doc_tables.py nor marked '{REFERENCE}': {lines[number - 1][:60]}")
        for name, span in spans.items():
            if name in where:
                problems.append(f"{path}:{span[0]}: table {name} also has a block in {where[name][0]}")
            where[name] = (path, span)
            if name not in tables:
                problems.append(f"{path}:{span[0]}: table {name} is in no registry of "
                                "scripts/doc_tables_registry.py")
    for name, table in sorted(tables.items()):
        if name not in where or where[name][0] != table.doc:
            problems.append(f"table {name}: no block '<!-- table {name} -->' in {table.doc}")
            continue
        if name in not_measured:
            if name in raws:
                problems.append(f"table {name}: doc/tables/{name}.txt is stored: take it off "
                                "NOT_YET_MEASURED")
            continue
        if name not in raws:
            problems.append(f"table {name}: no stored output doc/tables/{name}.txt (run "
                            f"scripts/doc_tables.py {name} --write)")
            continue
        if isinstance(raws[name], str):
            problems.append(f"table {name}: {raws[name]}")
            continue
        try:
            expected = table.block(raws[name]).split("\n")
        except ValueError as e:
            problems.append(f"table {name}: its stored output does not format: {e}")
            continue
        path, (a, b) = where[name]
        actual = docs[path].split("\n")[a:b - 1]
        while actual and not actual[0].strip():
            actual = actual[1:]
        while actual and not actual[-1].strip():
            actual = actual[:-1]
        if actual != expected:
            diff = next((i for i, (x, y) in enumerate(zip(actual, expected)) if x != y),
                        min(len(actual), len(expected)))
            problems.append(f"{path}:{a + 1 + diff}: table {name} differs from what "
                            f"scripts/doc_tables.py formats from doc/tables/{name}.txt "
                            f"(a figure edited by hand?): "
                            f"{actual[diff] if diff < len(actual) else '(missing line)'!r} "
                            f"against {expected[diff] if diff < len(expected) else '(nothing)'!r}")
    for path, header in sorted(set(not_yet) - seen):
        problems.append(f"{path}: no unscripted table '{header}' any more: take it off "
                        "NOT_YET_SCRIPTED")
    for name in sorted(set(raws) - set(tables)):
        problems.append(f"doc/tables/{name}.txt: no table {name} in the registry")
    return problems


def repository_problems():
    from doc_tables_registry import TABLES
    docs = {}
    for path in [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "doc", "*.md"))):
        with open(path, encoding="utf-8") as f:
            docs[os.path.relpath(path, ROOT)] = f.read()
    raws = {}
    for path in sorted(glob.glob(os.path.join(doc_tables.TABLES_DIR, "*.txt"))):
        name = os.path.basename(path)[:-4]
        try:
            raws[name] = doc_tables.load_raw(name)
        except ValueError as e:
            raws[name] = str(e)
    return check(docs, TABLES, raws, NOT_YET_SCRIPTED, NOT_YET_MEASURED)


def fake_table():
    """A table whose one run prints a number; its one row is that number and its square."""
    def rows(out):
        x = float(out["x"])
        return [["x", f"{x:g}", f"{x * x:g}"]]
    return doc_tables.Table("fake", "doc/fake.md", ["what", "x", "x squared"],
                            [doc_tables.Run("x", ["echo", "3"])], rows, "`echo 3`")


def fake_raw(value="3"):
    return doc_tables.Raw("abc1234", [], "2026-12-05", "-", {"x": ("echo 3", value + "\n", 0)})


def fake_doc(block, before="", after=""):
    return f"# Fake\n\n{before}<!-- table fake -->\n{block}\n<!-- /table fake -->\n{after}"


class Finder(unittest.TestCase):
    def test_a_block_as_its_script_formats_it_passes(self):
        block = fake_table().block(fake_raw())
        self.assertEqual(check({"doc/fake.md": fake_doc(block)}, {"fake": fake_table()},
                               {"fake": fake_raw()}), [])

    def test_a_figure_edited_by_hand_fails(self):
        block = fake_table().block(fake_raw()).replace("| x | 3 | 9 |", "| x | 3 | 10 |")
        problems = check({"doc/fake.md": fake_doc(block)}, {"fake": fake_table()},
                         {"fake": fake_raw()})
        self.assertEqual(len(problems), 1)
        self.assertIn("'| x | 3 | 10 |' against '| x | 3 | 9 |'", problems[0])

    def test_a_figure_its_stored_output_does_not_hold_fails(self):
        block = fake_table().block(fake_raw("4"))
        problems = check({"doc/fake.md": fake_doc(block)}, {"fake": fake_table()},
                         {"fake": fake_raw("3")})
        self.assertEqual(len(problems), 1)
        self.assertIn("differs from what scripts/doc_tables.py formats", problems[0])

    def test_a_stored_output_of_another_command_fails(self):
        raw = fake_raw()
        raw.runs["x"] = ("echo 4", "3\n", 0)
        block = fake_table().block(fake_raw())
        problems = check({"doc/fake.md": fake_doc(block)}, {"fake": fake_table()}, {"fake": raw})
        self.assertEqual(len(problems), 1)
        self.assertIn("was stored from 'echo 4', its command is now 'echo 3'", problems[0])

    def test_an_unmarked_table_fails(self):
        block = fake_table().block(fake_raw())
        doc = fake_doc(block, after="\n| a | b |\n|---|---|\n| 1 | 2 |\n")
        problems = check({"doc/fake.md": doc}, {"fake": fake_table()}, {"fake": fake_raw()})
        self.assertEqual(len(problems), 1)
        self.assertIn("doc/fake.md:11: a table neither written", problems[0])

    def test_a_table_marked_reference_passes(self):
        block = fake_table().block(fake_raw())
        doc = fake_doc(block, after=f"\n{REFERENCE}\n| a | b |\n|---|---|\n| 1 | 2 |\n")
        self.assertEqual(check({"doc/fake.md": doc}, {"fake": fake_table()},
                               {"fake": fake_raw()}), [])

    def test_a_reference_marker_two_lines_above_does_not_count(self):
        doc = f"# Fake\n\n{REFERENCE}\n\n| a | b |\n|---|---|\n"
        self.assertEqual(len(check({"doc/fake.md": doc}, {}, {})), 1)

    def test_a_table_inside_a_code_fence_is_no_table(self):
        doc = "# Fake\n\n```\n| a | b |\n|---|---|\n```\n"
        self.assertEqual(check({"doc/fake.md": doc}, {}, {}), [])

    def test_a_table_not_yet_scripted_is_not_reported_and_its_stale_entry_is(self):
        doc = "# Fake\n\n| a | b |\n|---|---|\n"
        self.assertEqual(check({"doc/fake.md": doc}, {}, {}, {("doc/fake.md", "| a | b |"): ""}), [])
        problems = check({"doc/fake.md": "# Fake\n"}, {}, {}, {("doc/fake.md", "| a | b |"): ""})
        self.assertEqual(len(problems), 1)
        self.assertIn("take it off NOT_YET_SCRIPTED", problems[0])

    def test_a_table_not_yet_measured_is_not_compared_until_its_output_is_stored(self):
        doc = fake_doc("| what | x | x squared |\n|---|---|---|\n| x | 3 | 10 |")
        self.assertEqual(check({"doc/fake.md": doc}, {"fake": fake_table()}, {}, (), {"fake": ""}), [])
        problems = check({"doc/fake.md": doc}, {"fake": fake_table()}, {"fake": fake_raw()}, (),
                         {"fake": ""})
        self.assertTrue(any("take it off NOT_YET_MEASURED" in p for p in problems), problems)

    def test_a_registered_table_without_its_block_fails(self):
        problems = check({"doc/fake.md": "# Fake\n"}, {"fake": fake_table()}, {"fake": fake_raw()})
        self.assertEqual(problems, ["table fake: no block '<!-- table fake -->' in doc/fake.md"])

    def test_a_registered_table_without_stored_output_fails(self):
        block = fake_table().block(fake_raw())
        problems = check({"doc/fake.md": fake_doc(block)}, {"fake": fake_table()}, {})
        self.assertEqual(len(problems), 1)
        self.assertIn("no stored output doc/tables/fake.txt", problems[0])

    def test_a_block_no_registry_entry_writes_fails(self):
        block = fake_table().block(fake_raw())
        problems = check({"doc/fake.md": fake_doc(block)}, {}, {})
        self.assertEqual(len(problems), 1)
        self.assertIn("table fake is in no registry", problems[0])

    def test_an_unclosed_block_fails(self):
        problems = check({"doc/fake.md": "<!-- table fake -->\n| a |\n|---|\n"}, {}, {})
        self.assertIn("doc/fake.md: table fake is never closed", problems)

    def test_the_stored_output_reads_back_as_written(self):
        raw = doc_tables.Raw("abc1234", ["src/a.cpp"], "2026-12-05", "bin/x=t",
                             {"k": ("echo '## not a mark'", "a\n## not a mark\n", 1)})
        back = doc_tables.Raw.parse(raw.text("fake"), "fake.txt")
        self.assertEqual((back.commit, back.changed, back.date, back.built, back.runs),
                         (raw.commit, raw.changed, raw.date, raw.built, raw.runs))


class Repository(unittest.TestCase):
    def test_every_table_of_the_docs_is_written_by_its_script_or_marked_reference(self):
        problems = repository_problems()
        self.assertEqual(problems, [], "\n" + "\n".join(problems))


if __name__ == "__main__":
    run_unittests(sys.argv, "doc_tables", "EveryMeasuredTableWrittenByItsScript")
