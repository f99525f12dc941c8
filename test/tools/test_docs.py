#!/usr/bin/python3
"""The docs as a guide (issue 42, item 6): README.md is at most 250 lines and starts with the
title, the picture and the two commands (`bash scripts/demo.sh`, `bash scripts/test.sh`); every
relative link and image of README.md and doc/*.md names a file that exists, and a link to a
heading of a Markdown file (`page.md#heading`, `#heading`) names a heading that file has (as
GitHub makes anchors from headings). Links inside code are not links. With
--gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import glob
import os
import re
import sys
import unittest

from gtest_xml import run_unittests

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
README = os.path.join(ROOT, "README.md")
MAX_README_LINES = 250
COMMANDS = ("bash scripts/demo.sh", "bash scripts/test.sh")
FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"(`+)(.+?)\1")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto:, ...


def doc_files():
    return [README] + sorted(glob.glob(os.path.join(ROOT, "doc", "*.md")))


def prose_lines(path):
    """(line number, text) of a Markdown file's lines outside fenced code blocks."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    fenced = False
    for number, line in enumerate(lines, 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield number, line


def links(path):
    """(line number, target) of every link and image outside code."""
    for number, line in prose_lines(path):
        for match in LINK.finditer(INLINE_CODE.sub(lambda m: "x" * len(m.group(0)), line)):
            yield number, match.group(1)


def anchor(heading):
    """GitHub's anchor of a heading's text: lower case, punctuation but - and _ dropped, spaces
    to hyphens."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link: its text
    text = text.replace("`", "").strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    """The anchors of a Markdown file's headings (a repeated one gets -1, -2, ... as on GitHub)."""
    seen, result = {}, set()
    for _, line in prose_lines(path):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        base = anchor(m.group(1))
        n = seen.get(base, 0)
        seen[base] = n + 1
        result.add(base if n == 0 else f"{base}-{n}")
    return result


class Docs(unittest.TestCase):
    def test_the_readme_is_at_most_250_lines(self):
        with open(README, encoding="utf-8") as f:
            count = len(f.read().splitlines())
        self.assertLessEqual(count, MAX_README_LINES, f"README.md has {count} lines")

    def test_the_readme_starts_with_the_title_the_picture_and_the_two_commands(self):
        with open(README, encoding="utf-8") as f:
            head = f.read().splitlines()[:12]
        self.assertTrue(head and head[0].startswith("# "), f"no title first: {head[:1]}")
        self.assertTrue(any(line.startswith("![") for line in head[1:4]), "no picture after the title")
        fence = next((i for i, line in enumerate(head) if line.strip() == "```bash"), None)
        self.assertIsNotNone(fence, "no ```bash block in the first lines")
        block = []
        for line in head[fence + 1:]:
            if line.strip().startswith("```"):
                break
            block.append(line)
        commands = [line.split("#")[0].strip() for line in block]
        self.assertEqual(commands, list(COMMANDS), f"the first block is not the two commands: {block}")

    def test_every_relative_link_names_a_file_that_exists(self):
        missing = []
        for path in doc_files():
            for number, target in links(path):
                if EXTERNAL.match(target) or target.startswith("#"):
                    continue
                file = target.split("#", 1)[0]
                resolved = os.path.normpath(os.path.join(os.path.dirname(path), file))
                if not os.path.exists(resolved):
                    missing.append(f"{os.path.relpath(path, ROOT)}:{number}: {target}")
        self.assertEqual(missing, [], "links to files that do not exist")

    def test_every_link_to_a_heading_names_a_heading_of_its_page(self):
        wrong = []
        for path in doc_files():
            for number, target in links(path):
                if EXTERNAL.match(target) or "#" not in target:
                    continue
                file, _, fragment = target.partition("#")
                page = os.path.normpath(os.path.join(os.path.dirname(path), file)) if file else path
                if not page.endswith(".md") or not os.path.exists(page):
                    continue  # a missing file is the test above's
                if fragment not in anchors(page):
                    wrong.append(f"{os.path.relpath(path, ROOT)}:{number}: {target}")
        self.assertEqual(wrong, [], "links to headings that do not exist")

    def test_the_checks_see_links_and_headings(self):
        self.assertGreater(sum(1 for path in doc_files() for _ in links(path)), 50)
        self.assertIn("launch-arguments", anchors(os.path.join(ROOT, "doc", "ros_interface.md")))
        self.assertEqual(anchor("The paper's Fig. 7 and 8, and `held-out` starts"),
                         "the-papers-fig-7-and-8-and-held-out-starts")


if __name__ == "__main__":
    run_unittests(sys.argv, "docs", "DocsAreAGuide")
