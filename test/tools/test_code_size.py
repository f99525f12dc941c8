#!/usr/bin/python3
"""test/tools/code_size.py finds what it missed: the first function after `namespace {` and after
a class's `public:`, a function defined in a class body, a lambda in a table or passed to a call,
a function whose signature spans several lines; include/, bench/ and test/ are scanned (test
files may have 800 lines). Each on a synthetic snippet one line over the limit (reported) and
at it (not reported). Class, struct and union bodies are measured too (300 lines: a class, a
struct in a namespace, a class template, one nested in another), enums are not; a class's size
counts the out-of-line definitions of its member functions in any file (a class under the limit
in its body and over it with them is reported; `World::Impl::x` is World::Impl's, not World's;
a template's, a constructor's, a destructor's and an operator's definition are the class's, a
free function in a namespace is nobody's, two classes of one name in two files are two). With
--gtest_output=xml:FILE also writes a gtest-style result for
catkin_test_results.
"""
import os
import shutil
import sys
import tempfile
import unittest

from code_size import (MAX_CLASS_LINES, MAX_FUNCTION_LINES, check, class_problems, classes,
                       file_problems, functions)
from gtest_xml import run_unittests


def body(lines):
    """`lines` statements of a function's body."""
    return [f"  x += {i};" for i in range(lines)]


def function(length, signature=("void f(int x) {",), indent=""):
    """A function of `length` lines from the first line of its `signature` to its `}`."""
    lines = list(signature) + body(length - len(signature) - 1) + ["}"]
    return [indent + line for line in lines]


def lengths(lines):
    """{what: length} of every function and lambda in `lines`."""
    return {what: last - first + 1 for what, first, last in functions(lines)}


class CodeSize(unittest.TestCase):
    def assert_reported(self, make, what, rel="src/a.cpp", max_file_lines=500):
        """The snippet make(length) is reported as `what` one line over the limit, not at it."""
        over = file_problems(rel, make(MAX_FUNCTION_LINES + 1), max_file_lines)
        self.assertEqual(len(over), 1, over)
        self.assertIn(f"{what} has {MAX_FUNCTION_LINES + 1} lines", over[0])
        self.assertEqual(file_problems(rel, make(MAX_FUNCTION_LINES), max_file_lines), [])

    def test_the_first_function_after_an_anonymous_namespace_is_measured(self):
        self.assert_reported(lambda n: ["namespace {"] + function(n) + ["}  // namespace"],
                             "function f")

    def test_the_first_function_after_a_named_namespace_is_measured(self):
        self.assert_reported(
            lambda n: ["#include <x>", "namespace flapsim {", "namespace detail {"] + function(n)
            + ["}", "}"], "function f")

    def test_functions_after_access_labels_and_in_class_bodies_are_measured(self):
        for label in ("public:", "private:", "protected:"):
            self.assert_reported(
                lambda n: ["class X {", f" {label}"] + function(n, indent="  ") + ["};"],
                "function f")
        self.assert_reported(  # after a member and a label, in a struct in a namespace
            lambda n: ["namespace {", "struct X : public Y {", "  int a_ = 0;", " private:"]
            + function(n, ("void g() const override {",), "  ") + ["};", "}"], "function g")

    def test_a_lambda_in_a_table_is_measured(self):
        self.assert_reported(
            lambda n: ["const std::map<std::string, std::function<void(int&)>> kTable = {",
                       '    {"a", [](int& x) { x = 1; }},',
                       '    {"b", [](int& x) {'] + body(n - 2) + ["     }},", "};"],
            "lambda")

    def test_a_lambda_in_a_function_is_measured_on_its_own(self):
        def make(n):
            return (["void f(std::vector<int>& v) {", "  std::sort(v.begin(), v.end(),",
                     "            [&](int a,", "                int b) mutable -> bool {"]
                    + body(n - 3) + ["            });", "}"])
        for n in (MAX_FUNCTION_LINES, MAX_FUNCTION_LINES + 1):  # f is 3 lines longer
            self.assertEqual(lengths(make(n)), {"lambda in f": n, "function f": n + 3})
        over = file_problems("src/a.cpp", make(MAX_FUNCTION_LINES + 1), 500)
        self.assertIn(f"src/a.cpp:3: lambda in f has {MAX_FUNCTION_LINES + 1} lines", over[0])

    def test_a_function_is_measured_from_the_first_line_of_a_long_signature(self):
        signature = ("template <typename T>", "std::map<std::string, double> Foo<T>::fit(",
                     "    const std::vector<T>& samples,", "    const Options& options = {},",
                     "    double tolerance = 1e-9) const {")
        self.assert_reported(lambda n: function(n, signature), "function Foo<T>::fit")
        for last in ("      c_{std::max(a, b)} {", "      c_(std::max(a, b)) {"):
            constructor = ("Foo::Foo(int a, int b)", "    : a_{a},", "      b_(b),", last)
            self.assert_reported(lambda n: function(n, constructor), "function Foo::Foo")

    def test_gtest_cases_are_measured_by_their_names(self):
        self.assert_reported(lambda n: function(n, ("TEST(Suite, LongCase) {",)),
                             "function TEST(Suite, LongCase)", "test/test_a.cpp", 800)

    def test_braces_in_comments_literals_and_preprocessor_lines_do_not_count(self):
        noise = ['  const char* s = "{ \\" {";  // {', "  char c = '{';", "  int k = 1'000'000;",
                 '  auto r = R"x(', "  { )\" {", '  )x";', "  /* {", "   { */ x += '}';",
                 "#define OPEN {"]
        make = lambda n: ["namespace {"] + function(n, ("void f() {",) + tuple(noise))
        self.assert_reported(make, "function f")
        self.assertEqual(lengths(make(MAX_FUNCTION_LINES))["function f"], MAX_FUNCTION_LINES)

    def test_if_blocks_and_initialisers_are_not_functions(self):
        lines = (["namespace {", "const int kN{3};", "int a[] = {1, 2};", "}",
                  "extern \"C\" {", "enum class E : int { kA, kB };"]
                 + function(5, ("int g() {", "  if (x) {", "  } else {", "  }")) + ["}"])
        self.assertEqual(lengths(lines), {"function g": 5})


def class_body(length, head="class X {", indent=""):
    """A class body of `length` lines from its `head` line to its `};`, members only."""
    members = [f"  int a{i}_ = 0;" for i in range(length - 2)]
    return [indent + line for line in [head] + members + ["};"]]


class ClassSize(unittest.TestCase):
    def assert_reported(self, make, what):
        """make(length) is reported as `what` one line over MAX_CLASS_LINES, not at it."""
        over = file_problems("include/a.h", make(MAX_CLASS_LINES + 1), 500)
        self.assertEqual(len(over), 1, over)
        self.assertIn(f"{what} has {MAX_CLASS_LINES + 1} lines (at most {MAX_CLASS_LINES})",
                      over[0])
        self.assertEqual(file_problems("include/a.h", make(MAX_CLASS_LINES), 500), [])

    def test_a_class_body_over_the_limit_is_reported(self):
        self.assert_reported(lambda n: class_body(n), "class X")

    def test_a_struct_in_a_namespace_with_a_base_is_reported(self):
        self.assert_reported(
            lambda n: ["namespace a {"] + class_body(n, "struct Y : public Base {") + ["}"],
            "class Y")

    def test_a_class_template_is_measured_from_its_template_line(self):
        self.assert_reported(
            lambda n: ["template <class T>"] + class_body(n - 1, "class Z {"), "class Z")

    def test_a_nested_class_is_measured_on_its_own(self):
        def outer_and_inner(n):
            return ["class Outer {", " public:"] + class_body(n, "struct Inner {", "  ") + ["};"]
        over = file_problems("include/a.h", outer_and_inner(MAX_CLASS_LINES + 1), 500)
        self.assertEqual([p.split(": ")[1] for p in over],
                         [f"class Outer has {MAX_CLASS_LINES + 4} lines (at most "
                          f"{MAX_CLASS_LINES})",
                          f"class Outer::Inner has {MAX_CLASS_LINES + 1} lines (at most "
                          f"{MAX_CLASS_LINES})"])

    def test_an_enum_is_not_a_class_and_a_member_function_stays_a_function(self):
        enum = ["enum class E {"] + [f"  k{i}," for i in range(MAX_CLASS_LINES + 5)] + ["};"]
        self.assertEqual(file_problems("include/a.h", enum, 500), [])
        body = ["class X {", " public:"] + function(MAX_FUNCTION_LINES + 1, indent="  ") + ["};"]
        self.assertEqual(list(classes(body)), [("class X", 1, len(body))])
        self.assertEqual([w for w, _, _ in functions(body)], ["function f"])


def members(length, owner, names="f"):
    """Out-of-line member functions `void owner::f0() {...}`, ... of `length` lines in all, none
    over the function limit."""
    lines, i = [], 0
    while length > 0:
        n = min(length, MAX_FUNCTION_LINES)
        lines += function(n, (f"void {owner}::{names}{i}() {{",)) if n > 1 else [
            f"void {owner}::{names}{i}() {{}}"]
        length, i = length - n, i + 1
    return lines


class OutOfLineMembers(unittest.TestCase):
    def assert_reported(self, make, what, body):
        """make(n) ({rel: lines}) has `what` at n = MAX_CLASS_LINES + 1 lines, counted as its
        `body` and its members, and nothing at MAX_CLASS_LINES."""
        over = class_problems(make(MAX_CLASS_LINES + 1))
        self.assertEqual(len(over), 1, over)
        self.assertIn(f"class {what} has {MAX_CLASS_LINES + 1} lines (at most {MAX_CLASS_LINES})"
                      f" counting its out-of-line members: its body {body}", over[0])
        self.assertEqual(class_problems(make(MAX_CLASS_LINES)), [])

    def test_a_class_under_the_limit_in_its_body_is_over_it_with_its_members_elsewhere(self):
        body = class_body(100, "class Solver {")
        make = lambda n: {"src/a/solver.h": ["namespace flapsim {"] + body + ["}"],
                          "src/a/solver.cpp": ["namespace flapsim {"] + members(n - 100, "Solver")
                          + ["}"]}
        self.assert_reported(make, "Solver", 100)
        header = make(MAX_CLASS_LINES + 1)["src/a/solver.h"]
        self.assertEqual(file_problems("src/a/solver.h", header, 500), [])  # its body alone fits
        over = class_problems(make(MAX_CLASS_LINES + 1))
        self.assertTrue(over[0].startswith("src/a/solver.h:2: class Solver"), over)
        self.assertIn(f"its member functions {MAX_CLASS_LINES + 1 - 100} in src/a/solver.cpp "
                      "(3 functions)", over[0])

    def test_members_in_several_files_of_several_trees_add_up(self):
        body = class_body(101, "struct Stage {")
        make = lambda n: {"include/x/stage.h": body, "src/stage.cpp": members(100, "Stage"),
                          "test/test_stage.cpp": members(n - 201, "Stage", "g")}
        self.assert_reported(make, "Stage", 101)

    def test_a_nested_class_s_members_are_its_own_not_the_outer_class_s(self):
        header = ["class World {", " public:", "  void step();", " private:", "  struct Impl;",
                  "};"]
        impl = class_body(50, "struct World::Impl {")
        make = lambda n: {"include/world.h": header,
                          "src/world.cpp": impl + members(n - 50, "World::Impl") + members(
                              3, "World", "step")}
        self.assert_reported(make, "World::Impl", 50)
        over = class_problems(make(MAX_CLASS_LINES + 1))
        self.assertTrue(over[0].startswith("src/world.cpp:1: class World::Impl has"), over)
        inner = ["class Outer {", " public:"] + class_body(20, "struct Inner {", "  ") + ["};"]
        make = lambda n: {"include/outer.h": inner, "src/outer.cpp": members(n - 20,
                                                                              "Outer::Inner")}
        self.assert_reported(make, "Outer::Inner", 20)

    def test_templates_constructors_destructors_operators_and_namespaces_are_the_class_s(self):
        head = ["namespace flapsim {", "template <class T>"] + class_body(10, "class Fit {") + [
            "}"]
        defined = (function(20, ("template <class T>", "Fit<T>::Fit(int a)", "    : a_(a),",
                                 "      b_{a} {"))
                   + function(20, ("template <class T>", "Fit<T>::~Fit() {"))
                   + function(20, ("template <class T>",
                                   "Fit<T>& Fit<T>::operator=(const Fit<T>& o) {"))
                   + function(20, ("template <class T>", "bool flapsim::Fit<T>::operator<(",
                                   "    const Fit<T>& o) const {"))
                   + function(80, ("void detail::free() {",)))  # a namespace's: nobody's
        make = lambda n: {"include/fit.h": head,
                          "src/fit.cpp": defined + members(n - 91, "flapsim::Fit<T>")}
        self.assert_reported(make, "Fit", 11)

    def test_classes_of_one_name_in_two_files_are_counted_apart(self):
        local = ["namespace {"] + class_body(100, "struct Options {") + ["}"]
        make = lambda n: {"src/a.cpp": local + members(n - 100, "Options"),
                          "src/b.cpp": local + members(n - 100, "Options")}
        over = class_problems(make(MAX_CLASS_LINES + 1))
        self.assertEqual([p.split(":")[0] for p in over], ["src/a.cpp", "src/b.cpp"])
        self.assertEqual(class_problems(make(MAX_CLASS_LINES)), [])

    def test_a_member_defined_in_its_class_body_is_counted_once(self):
        body = (["class X {", " public:"] + function(80, indent="  ")
                + [f"  int a{i}_ = 0;" for i in range(MAX_CLASS_LINES - 83)] + ["};"])
        self.assertEqual(class_problems({"include/x.h": body, "src/x.cpp": []}), [])
        over = class_problems({"include/x.h": body, "src/x.cpp": ["void X::g() {}"]})
        self.assertIn(f"class X has {MAX_CLASS_LINES + 1} lines", over[0])


class Trees(unittest.TestCase):
    def setUp(self):
        self.root = tempfile.mkdtemp(prefix="flapsim_code_size_")

    def tearDown(self):
        shutil.rmtree(self.root, ignore_errors=True)

    def write(self, rel, lines):
        path = os.path.join(self.root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")

    def test_every_tree_and_cpp_extension_is_scanned_for_long_functions(self):
        for rel in ("src/a/b.cpp", "include/x/y.h", "include/x/z.hpp", "bench/b.cc",
                    "test/ros/test_t.cpp", "test/test_util.h"):
            self.write(rel, function(MAX_FUNCTION_LINES + 1))
            self.write(rel.replace(".", "_ok."), function(MAX_FUNCTION_LINES))
        self.write("doc/d.cpp", function(MAX_FUNCTION_LINES + 1))  # not a tree of code
        self.write("bench/b.py", ["x = 1"] * 900)
        self.assertEqual(sorted(p.split(":")[0] for p in check(self.root)),
                         ["bench/b.cc", "include/x/y.h", "include/x/z.hpp", "src/a/b.cpp",
                          "test/ros/test_t.cpp", "test/test_util.h"])

    def test_test_files_may_have_800_lines_and_the_others_500(self):
        for tree, limit in (("test", 800), ("test/ros", 800), ("src", 500), ("include", 500),
                            ("bench", 500)):
            self.write(f"{tree}/over.cpp", ["int x;"] * (limit + 1))
            self.write(f"{tree}/at.cpp", ["int x;"] * limit)
        self.assertEqual(sorted(check(self.root)),
                         ["bench/over.cpp: 501 lines (at most 500)",
                          "include/over.cpp: 501 lines (at most 500)",
                          "src/over.cpp: 501 lines (at most 500)",
                          "test/over.cpp: 801 lines (at most 800)",
                          "test/ros/over.cpp: 801 lines (at most 800)"])

    def test_the_tree_s_check_counts_out_of_line_members_in_other_trees(self):
        self.write("include/x/big.h", class_body(200, "class Big {"))
        self.write("src/big.cpp", members(MAX_CLASS_LINES + 1 - 200, "Big"))
        self.write("include/x/fits.h", class_body(200, "class Fits {"))
        self.write("bench/fits.cpp", members(MAX_CLASS_LINES - 200, "Fits"))
        self.assertEqual([p.split(": ")[1] for p in check(self.root)],
                         [f"class Big has {MAX_CLASS_LINES + 1} lines (at most {MAX_CLASS_LINES})"
                          " counting its out-of-line members"])


if __name__ == "__main__":
    run_unittests(sys.argv, "code_size_finder", "FindsEveryFunctionAndFile")
