#!/usr/bin/python3
"""One convention for the launch arguments (issue 42, item 5): every <arg> of launch/*.launch has
a doc; every argument one can set is a row of doc/ros_interface.md's "Launch arguments" table,
whose files column names exactly the files that declare it (one name, one meaning); a vector
argument (`wind`) defaults to three numbers and reaches the node as a list of three numbers
(loaded with roslaunch's own loader, no master: with its default, with wind:="0 1 0", and
wind:=1 refused); afc.launch real_air:=true sets the air, the noises and the disturbance node,
and refuses wind, turbulence, imu_noise and altitude_noise beside it. Argument: the devel prefix (the loader runs with its setup.bash). With
--gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import glob
import json
import os
import re
import subprocess
import sys
import unittest
import xml.etree.ElementTree as ET

from gtest_xml import run_unittests

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DEVEL = sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else None
NUMBER = r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?"
# the vector arguments and the parameter each sets; the table's "three numbers" rows
VECTOR_PARAMS = {"wind": "/flapsim/air/wind"}
LOAD = """
import json, sys, roslaunch.config, roslaunch.xmlloader
out = []
for path, args in json.loads(sys.argv[1]):
    config = roslaunch.config.ROSLaunchConfig()
    try:
        roslaunch.xmlloader.XmlLoader(resolve_anon=False).load(
            path, config, argv=['roslaunch'] + args, verbose=False)
        out.append({k: p.value for k, p in config.params.items()})
    except Exception as e:
        out.append({'error': str(e)})
print(json.dumps(out))
"""


def launch_files():
    """{stem: ElementTree root} of launch/*.launch."""
    return {os.path.basename(p)[:-len(".launch")]: ET.parse(p).getroot()
            for p in sorted(glob.glob(os.path.join(ROOT, "launch", "*.launch")))}


def declared_args(root):
    """The <arg> elements a file declares (not those an <include> passes on)."""
    passed = {id(a) for include in root.iter("include") for a in include.findall("arg")}
    return [a for a in root.iter("arg") if id(a) not in passed]


def settable(arg):
    """An argument one can set (a default or required), not a value computed in the file."""
    return arg.get("value") is None


def includes(root, stem):
    return any(i.get("file", "").endswith("/" + stem + ".launch") for i in root.iter("include"))


def scenarios(files):
    return {f for f, root in files.items() if includes(root, "simulator") and includes(root, "views")}


def doc_section():
    """The lines of doc/ros_interface.md's "## Launch arguments" section."""
    with open(os.path.join(ROOT, "doc", "ros_interface.md")) as f:
        lines = f.read().splitlines()
    start = lines.index("## Launch arguments")
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("#")), len(lines))
    return lines[start + 1:end]


def doc_table(section, groups):
    """{name: (meaning, unit, default, set of files)} of the section's table rows."""
    rows = {}
    for line in section:
        if not line.startswith("| `"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        assert len(cells) == 5, f"not 5 cells: {line}"
        files = set()
        for token in cells[4].replace("`", "").split(","):
            group, _, exception = token.strip().partition(" except ")
            files |= groups.get(group, {group}) - set(exception.split())
        for name in re.findall(r"`([a-z_]+)`", cells[0]):
            assert name not in rows, f"{name}: two rows"
            rows[name] = (cells[1], cells[2], cells[3], files)
    return rows


class LaunchArgs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.files = launch_files()
        cls.scenarios = scenarios(cls.files)
        cls.section = doc_section()
        cls.table = doc_table(cls.section, {"scenarios": cls.scenarios})
        cls.declared = {}  # settable name: {file: <arg>}
        for f, root in cls.files.items():
            for a in declared_args(root):
                if settable(a):
                    cls.declared.setdefault(a.get("name"), {})[f] = a

    def test_files_and_table_were_read(self):
        self.assertIn("hover", self.files)
        self.assertEqual(len(self.scenarios), 9, sorted(self.scenarios))
        self.assertGreater(len(self.table), 40)
        self.assertIn("wind", self.table)

    def test_the_doc_names_the_scenarios(self):
        text = " ".join(self.section)
        listed = re.search(r"\*scenarios\*: ([a-z_, ]+)", text)
        self.assertIsNotNone(listed, "no '*scenarios*: ...' in the section")
        self.assertEqual({s.strip() for s in listed.group(1).split(",")}, self.scenarios)

    def test_every_arg_has_a_doc(self):
        missing = [f"{f}.launch: {a.get('name')}" for f, root in self.files.items()
                   for a in declared_args(root) if not (a.get("doc") or "").strip()]
        self.assertEqual(missing, [], "<arg> without doc=")

    def test_an_eval_reads_only_args_declared_before_it(self):
        """roslaunch evaluates a default's $(eval ...) when it reaches it: an arg it reads that is
        declared further down is undefined there, and the file fails to launch for the values
        that reach that read (afc.launch's added_mass_products read `altitude` for the chains)."""
        for stem, root in self.files.items():
            seen = set()
            for arg in declared_args(root):
                for attr in ("default", "value"):
                    text = arg.get(attr) or ""
                    for name in re.findall(r"arg\('([A-Za-z0-9_]+)'\)", text):
                        self.assertIn(name, seen, f"{stem}.launch: {arg.get('name')} reads "
                                      f"{name}, declared after it")
                seen.add(arg.get("name"))

    def test_every_settable_arg_is_in_the_table(self):
        self.assertEqual(sorted(set(self.declared) - set(self.table)), [],
                         "declared in launch/ but not a row of the Launch arguments table")
        self.assertEqual(sorted(set(self.table) - set(self.declared)), [],
                         "a row of the table no launch file declares")

    def test_the_table_lists_exactly_the_files_that_declare_each_arg(self):
        wrong = {name: {"table": sorted(row[3]), "launch": sorted(self.declared.get(name, {}))}
                 for name, row in self.table.items()
                 if row[3] != set(self.declared.get(name, {}))}
        self.assertEqual(wrong, {})

    def test_a_computed_value_is_not_named_like_an_argument(self):
        clashes = [f"{f}.launch: {a.get('name')}" for f, root in self.files.items()
                   for a in declared_args(root)
                   if not settable(a) and a.get("name") in self.table]
        self.assertEqual(clashes, [])

    def test_vector_args_default_to_three_numbers(self):
        vectors = {n for n, row in self.table.items() if "three numbers" in row[1]}
        self.assertEqual(vectors, set(VECTOR_PARAMS), "the table's vectors and VECTOR_PARAMS")
        three = re.compile(rf"^{NUMBER} {NUMBER} {NUMBER}$")
        for name in vectors:
            for f, a in self.declared[name].items():
                self.assertRegex(a.get("default") or "", three, f"{f}.launch {name}'s default")

    @unittest.skipIf(DEVEL is None, "no devel prefix given")
    def test_vector_args_reach_the_node_as_three_numbers(self):
        cases, expected = [], []
        for f in sorted(self.scenarios):  # the node's wind: config/flapsim.yaml's, or the arg's
            cases.append((f, []))
            expected.append((VECTOR_PARAMS["wind"], [0, 0, 0]))
        for name, param in sorted(VECTOR_PARAMS.items()):
            for f in sorted(self.declared[name]):
                cases += [(f, [f"{name}:=0 1 0"]), (f, [f"{name}:=-1.5 2e-1 0"])]
                expected += [(param, [0, 1, 0]), (param, [-1.5, 0.2, 0])]
        results = self.load(cases + [(f, [f"{n}:=1"]) for n in VECTOR_PARAMS
                                                  for f in sorted(self.declared[n])])
        for (f, args), (param, value), params in zip(cases, expected, results):
            with self.subTest(launch=f, args=args):
                self.assertNotIn("error", params)
                got = params.get(param)
                self.assertIsInstance(got, list, f"{param}: {got!r}")
                self.assertEqual(len(got), 3, f"{param}: {got!r}")
                self.assertTrue(all(isinstance(v, (int, float)) for v in got), f"{got!r}")
                self.assertEqual(got, value)
        refused = results[len(cases):]
        for name in VECTOR_PARAMS:
            for f, params in zip(sorted(self.declared[name]), refused):
                with self.subTest(launch=f, args=f"{name}:=1"):
                    self.assertTrue("error" in params, f"a single number is not a vector: "
                                    f"{VECTOR_PARAMS[name]} = {params.get(VECTOR_PARAMS[name])!r}")
                    self.assertIn(f"{name} must be three numbers", params["error"])

    @unittest.skipIf(DEVEL is None, "no devel prefix given")
    def test_real_air_sets_the_air_the_noises_and_the_disturbance_and_refuses_what_it_sets(self):
        cases = [("afc", ["real_air:=true", "altitude:=4"]), ("afc", ["real_air:=true",
                 "real_air_seed:=5"]), ("afc", [])]
        refused = {"wind": "0 1 0", "turbulence": "moderate", "imu_noise": "0.1",
                   "altitude_noise": "0.1"}
        cases += [("afc", ["real_air:=true", f"{n}:={v}"]) for n, v in sorted(refused.items())]
        results = self.load(cases)
        drawn, other, plain = results[:3]
        for params in (drawn, other):
            self.assertNotIn("error", params)
            wind = params["/flapsim/air/wind"]
            self.assertEqual(len(wind), 3, wind)
            self.assertAlmostEqual(wind[0] ** 2 + wind[1] ** 2, 1.0, places=12)  # 1 m/s
            self.assertEqual(wind[2], 0)
            bias = params["/afc/ann_controller/gyro_bias"]
            self.assertEqual(len(bias), 3, bias)
            self.assertLessEqual(sum(b * b for b in bias), 0.02 ** 2)
            self.assertEqual(params["/flapsim/air/turbulence/level"], "light")
            self.assertEqual(params["/flapsim/imu/orientation_noise"], 0.05)
            self.assertEqual(params["/flapsim/imu/angular_velocity_noise"], 0.05)
            self.assertEqual(params["/afc/ann_controller/altitude_noise"], 0.05)
        self.assertEqual(drawn["/flapsim/air/turbulence/height"], 4.0)  # the altitude held
        self.assertEqual(drawn["/afc/disturbance/seed"], 2024)
        self.assertEqual(other["/afc/disturbance/seed"], 5)
        self.assertNotEqual(drawn["/flapsim/air/wind"], other["/flapsim/air/wind"])
        self.assertNotIn("/afc/disturbance/seed", plain)
        self.assertNotIn("/afc/ann_controller/gyro_bias", plain)
        for (_, args), params in zip(cases[3:], results[3:]):
            with self.subTest(args=args):
                name = args[1].split(":=")[0]
                self.assertIn("error", params, f"{args} was taken")
                self.assertIn(f"leave {name} unset, not {args[1]}", params["error"])

    def load(self, cases):
        """Each (file stem, args) loaded as roslaunch loads it: its parameters, or its error."""
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("ROS_", "CMAKE_PREFIX", "PYTHONPATH", "LD_LIBRARY_PATH"))}
        paths = [(os.path.join(ROOT, "launch", f + ".launch"), args) for f, args in cases]
        cmd = f"source '{os.path.join(DEVEL, 'setup.bash')}' && /usr/bin/python3 -c \"$0\" \"$1\""
        r = subprocess.run(["bash", "-c", cmd, LOAD, json.dumps(paths)], capture_output=True,
                           text=True, timeout=300, env=env)
        self.assertEqual(r.returncode, 0, r.stderr[-2000:])
        results = json.loads(r.stdout.strip().splitlines()[-1])
        self.assertEqual(len(results), len(cases))
        return results


if __name__ == "__main__":
    run_unittests(sys.argv, "launch_args", "OneConventionForLaunchArgs")
