#!/usr/bin/python3
"""The measured tables of the docs, written by their commands (issue 42, item 6).

usage: scripts/doc_tables.py NAME... [--write]     measure NAME now, print its table
       scripts/doc_tables.py NAME... --write-raw    the same, storing the raw output only
       scripts/doc_tables.py NAME... --reformat     re-format the stored raw output into the doc
       scripts/doc_tables.py --list                 the registry: name, doc, commands

Every table of README.md and doc/*.md that holds measured figures is registered here: its doc
file, the commands that measure it (the repository's own tools, run from the repository's top
directory), and a formatter that turns their standard output into markdown rows. Running NAME
runs the commands now, printing each command and the commit it ran on
(`git rev-parse --short HEAD`, and whether the tree had uncommitted changes); with --write it
stores the commands, the commit and the raw output in doc/tables/NAME.txt and rewrites the
doc's block between `<!-- table NAME -->` and `<!-- /table NAME -->`.

The formatter is a pure function of the stored raw output: test/tools/test_doc_tables.py
re-formats every doc/tables/*.txt and fails when a block differs (a figure edited by hand),
when a registered table has no block or no stored output, and when a table of the docs is
neither in a block nor marked `<!-- table reference -->` (definitions and defaults, not
measurements).
"""
import datetime
import glob
import os
import shlex
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
TABLES_DIR = os.path.join(ROOT, "doc", "tables")
RUN_MARK = "## run "
COMMAND_MARK = "## command "
EXIT_MARK = "## exit "


class Run:
    """One command of a table: a key naming it within the table, its argv (run from ROOT)."""

    def __init__(self, key, argv):
        self.key = key
        self.argv = list(argv)

    def command(self):
        return " ".join(shlex.quote(a) for a in self.argv)


class Table:
    """A measured table: its name, doc file (relative to ROOT), header row, runs, a function
    from {key: stdout} to the table's rows (lists of cells), and how its commands are said
    below the table (`said`: markdown, or a function from {key: stdout} to it when it says
    what the runs saw, such as the load average; the runs' full commands are in the stored raw
    file)."""

    def __init__(self, name, doc, header, runs, rows, said):
        self.name = name
        self.doc = doc
        self.header = header
        self.runs = runs
        self.rows = rows
        self.said = said

    def block(self, raw):
        """The markdown block (without its markers) from stored raw output, which must be the
        output of exactly this table's commands."""
        outputs = {key: out for key, (_, out, _) in raw.runs.items()}
        missing = [r.key for r in self.runs if r.key not in outputs]
        if missing:
            raise ValueError(f"table {self.name}: no stored output of run(s) {', '.join(missing)}")
        extra = sorted(set(outputs) - {r.key for r in self.runs})
        if extra:
            raise ValueError(f"table {self.name}: stored output of runs it has no more: "
                             f"{', '.join(extra)}")
        for run in self.runs:
            if raw.runs[run.key][0] != run.command():
                raise ValueError(f"table {self.name}: run {run.key!r} was stored from "
                                 f"'{raw.runs[run.key][0]}', its command is now "
                                 f"'{run.command()}': measure it again")
        link = os.path.relpath(os.path.join("doc", "tables", self.name + ".txt"),
                               os.path.dirname(self.doc))
        lines = ["| " + " | ".join(self.header) + " |", "|" + "---|" * len(self.header)]
        for row in self.rows(outputs):
            if len(row) != len(self.header):
                raise ValueError(f"table {self.name}: a row of {len(row)} cells for "
                                 f"{len(self.header)} columns: {row}")
            lines.append("| " + " | ".join(row) + " |")
        lines.append("")
        said = self.said(outputs) if callable(self.said) else self.said
        lines.append(f"Written by `scripts/doc_tables.py {self.name}` at commit {raw.commit}"
                     f"{' (uncommitted changes in the tree)' if raw.dirty else ''}, "
                     f"{raw.date}: {said}; commands and raw output: [{link}]({link}).")
        return "\n".join(lines)


class Raw:
    """The stored output of a table's runs: commit, the files changed since it (that can change
    a measurement), date, the programs' modification times and {key: (command, stdout, exit
    code)}."""

    def __init__(self, commit, changed, date, built, runs):
        self.commit = commit
        self.changed = changed
        self.dirty = bool(changed)
        self.date = date
        self.built = built
        self.runs = runs

    def text(self, name):
        out = [f"# doc table {name}: written by scripts/doc_tables.py {name} --write",
               f"# commit {self.commit}", f"# dirty {'yes' if self.dirty else 'no'}",
               f"# changed {' '.join(self.changed) if self.changed else '-'}",
               f"# date {self.date}", f"# built {self.built}"]
        for key, (command, stdout, code) in self.runs.items():
            out += [RUN_MARK + key, COMMAND_MARK + command, stdout.rstrip("\n"), EXIT_MARK + str(code)]
        return "\n".join(out) + "\n"

    @staticmethod
    def parse(text, source):
        head = {}
        runs = {}
        key = None
        body = []
        command = code = None
        for number, line in enumerate(text.split("\n"), 1):
            if key is None and line.startswith("# ") and not runs:
                parts = line[2:].split(" ", 1)
                head[parts[0]] = parts[1] if len(parts) > 1 else ""
            elif line.startswith(RUN_MARK):
                key = line[len(RUN_MARK):]
                body = []
                command = code = None
            elif line.startswith(COMMAND_MARK) and command is None and key is not None:
                command = line[len(COMMAND_MARK):]
            elif line.startswith(EXIT_MARK) and key is not None:
                code = int(line[len(EXIT_MARK):])
                runs[key] = (command, "\n".join(body) + "\n", code)
                key = None
            elif key is not None:
                body.append(line)
            elif line.strip():
                raise ValueError(f"{source}:{number}: a line outside any run: {line!r}")
        if key is not None:
            raise ValueError(f"{source}: run {key} has no exit line")
        for field in ("commit", "dirty", "changed", "date", "built"):
            if field not in head:
                raise ValueError(f"{source}: no '# {field}' line")
        changed = [] if head["changed"] == "-" else head["changed"].split()
        if (head["dirty"] == "yes") != bool(changed):
            raise ValueError(f"{source}: '# dirty' and '# changed' disagree")
        return Raw(head["commit"], changed, head["date"], head["built"], runs)


def raw_path(name):
    return os.path.join(TABLES_DIR, name + ".txt")


def load_raw(name):
    with open(raw_path(name), encoding="utf-8") as f:
        return Raw.parse(f.read(), os.path.relpath(raw_path(name), ROOT))


def block_markers(name):
    return f"<!-- table {name} -->", f"<!-- /table {name} -->"


def find_block(text, name):
    """(start, end) character offsets of the block's content between its markers, or None."""
    begin, end = block_markers(name)
    i = text.find(begin)
    if i < 0:
        return None
    j = text.find(end, i)
    if j < 0:
        raise ValueError(f"table {name}: '{begin}' without '{end}'")
    return i + len(begin), j


def write_block(table, block):
    path = os.path.join(ROOT, table.doc)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    where = find_block(text, table.name)
    if where is None:
        raise ValueError(f"{table.doc} has no '{block_markers(table.name)[0]}': add the markers "
                         "where the table goes")
    text = text[:where[0]] + "\n" + block + "\n" + text[where[1]:]
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def git(*args):
    return subprocess.run(["git", "-C", ROOT] + list(args), check=True, capture_output=True,
                          text=True).stdout


def changed_files():
    """The tracked files with uncommitted changes that can change a measurement (the docs and
    the stored tables cannot)."""
    paths = [line[3:] for line in git("status", "--porcelain", "--untracked-files=no").split("\n")
             if line.strip()]
    return [p for p in paths if not p.endswith(".md") and not p.startswith("doc/tables/")]


def built(table):
    """The modification time (UTC) of each program and of the libraries they load: a build may
    lag the commit."""
    programs = sorted({r.argv[0] for r in table.runs if os.sep in r.argv[0]})
    programs += sorted(os.path.relpath(p, ROOT) for p in
                       glob.glob(os.path.join(ROOT, "build", "devel", "lib", "libflapsim*.so")))
    stamps = []
    for program in programs:
        path = os.path.join(ROOT, program)
        if os.path.exists(path):
            mtime = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
            stamps.append(f"{program}={mtime.strftime('%Y-%m-%dT%H:%MZ')}")
    return " ".join(stamps) if stamps else "-"


_RAN = {}  # command -> its finished process, within one invocation


def measure(table):
    commit = git("rev-parse", "--short", "HEAD").strip()
    changed = changed_files()
    print(f"# {table.name} ({table.doc}) at commit {commit}"
          + (f", tree dirty: {', '.join(changed)}" if changed else ", tree clean"), flush=True)
    before = built(table)
    runs = {}
    for run in table.runs:
        print(f"$ {run.command()}", flush=True)
        # A command another table of this invocation ran is not run again: they are
        # deterministic.
        done = _RAN.get(run.command()) or run_once(table, run)
        _RAN[run.command()] = done
        runs[run.key] = (run.command(), done.stdout, done.returncode)
    after = built(table)
    if after != before:
        print(f"# {table.name}: rebuilt during the measurement (stored with both times)",
              flush=True)
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    return Raw(commit, changed, date,
               before if after == before else f"{before} ; rebuilt by the end: {after}", runs)


def run_once(table, run, attempts=10, wait=30):
    """Runs one command; a program missing or half-written (a rebuild under way: it cannot
    be started, or the loader fails, exit 127) is waited for and tried again."""
    import time
    for attempt in range(attempts):
        try:
            done = subprocess.run(run.argv, cwd=ROOT, capture_output=True, text=True)
        except OSError as e:
            failure = str(e)
        else:
            if done.returncode in (0, 1):  # flight_check exits 1 when a start fails
                return done
            if done.returncode != 127:
                sys.stderr.write(done.stderr)
                raise RuntimeError(f"table {table.name}: '{run.command()}' exited "
                                   f"{done.returncode}")
            failure = done.stderr.strip()
        print(f"# cannot run it now ({failure}): a rebuild? again in {wait} s", flush=True)
        time.sleep(wait)
    raise RuntimeError(f"table {table.name}: cannot run '{run.command()}' in {attempts} "
                       "attempts: build it")


def main(args):
    if "--help" in args or "-h" in args:
        print(__doc__.split("\n\n")[1])
        return 0
    from doc_tables_registry import TABLES
    if "--list" in args:
        for t in TABLES.values():
            said = t.said if not callable(t.said) else "; ".join(r.command() for r in t.runs)
            print(f"{t.name}\t{t.doc}\t{said}")
        return 0
    write = "--write" in args
    write_raw = "--write-raw" in args
    reformat = "--reformat" in args
    names = [a for a in args if not a.startswith("--")]
    unknown = [a for a in args if a.startswith("--") and a not in ("--write", "--write-raw", "--reformat")]
    if unknown or not names:
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        if unknown:
            sys.stderr.write(f"doc_tables.py: unknown option {unknown[0]}\n")
        return 2
    for name in names:
        if name not in TABLES:
            sys.stderr.write(f"doc_tables.py: no table named {name} (--list names them)\n")
            return 2
    for name in names:
        table = TABLES[name]
        if reformat:
            raw = load_raw(name)
        else:
            raw = measure(table)
        block = table.block(raw)
        print(block, flush=True)
        if write or write_raw:
            os.makedirs(TABLES_DIR, exist_ok=True)
            with open(raw_path(name), "w", encoding="utf-8") as f:
                f.write(raw.text(name))
        if write or reformat:
            write_block(table, block)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    try:
        sys.exit(main(sys.argv[1:]))
    except (OSError, RuntimeError, ValueError) as e:
        sys.stderr.write(f"doc_tables.py: {e}\n")
        sys.exit(1)
