"""The figures a gtest prints for the docs' tables (test/doc_figure.h's printFigure): lines
`[figure] Suite.Test name value` in the output of a test binary run with --gtest_filter."""
from doc_tables import Run

TEST_DIR = "build/devel/lib/flapsim/"


def gtest_run(binary, tests):
    """The run of `binary` (build/devel/lib/flapsim/NAME) on the gtests `tests`, keyed by the
    binary's name."""
    return Run(binary, [TEST_DIR + binary, "--gtest_filter=" + ":".join(tests)])


class Figures:
    """The figures of a set of gtest runs' output: {(Suite.Test, name): [values, in order]}.
    Every run must have passed all its tests, and every test asked for must have printed."""

    def __init__(self, outputs, source):
        self.values = {}
        self.source = source
        for key, text in outputs.items():
            if "[  PASSED  ]" not in text or "[  FAILED  ]" in text:
                raise ValueError(f"{source}: run {key} did not pass every test: measure it again "
                                 "on a build whose tests pass")
            for line in text.split("\n"):
                if line.startswith("[figure] "):
                    cells = line.split()
                    if len(cells) != 4:
                        raise ValueError(f"{source}: not a figure line: {line!r}")
                    self.values.setdefault((cells[1], cells[2]), []).append(float(cells[3]))

    def all(self, test, name):
        """Every value the test printed under `name`."""
        if (test, name) not in self.values:
            raise ValueError(f"{self.source}: {test} printed no figure {name}")
        return self.values[(test, name)]

    def one(self, test, name):
        values = self.all(test, name)
        if len(values) != 1:
            raise ValueError(f"{self.source}: {test} printed {name} {len(values)} times")
        return values[0]

    def matching(self, test, prefix):
        """{name: value} of the test's figures whose names start with `prefix`."""
        return {name[len(prefix):]: v[0] for (t, name), v in self.values.items()
                if t == test and name.startswith(prefix)}


def sci(x, digits=1):
    """A small figure in scientific notation: 1.8e-15; 0 for an exact zero."""
    return "0" if x == 0 else f"{x:.{digits}e}"


def pct(x, digits=2):
    """A fraction as a signed percentage: +1.13 %."""
    return f"{x * 100:+.{digits}f} %"


def span(values, fmt=sci):
    """'lowest to highest' of the values, or the one value when they are all alike."""
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo} to {hi}"
