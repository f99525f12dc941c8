#!/usr/bin/python3
"""CPU time of a spawn of a one-link creature whose collision is a ring mesh, as its convex
hull and as its convex decomposition (doc/urdf.md): rings of NU x NV quads made by
test/meshes/make_meshes.py (64 x 16 is test/meshes/ring.obj, 2048 triangles), each in a copy
of test/meshes/ring_hull.urdf and ring_decomposed.urdf, spawned by a whole
`flapsim_bench --urdf FILE --runs 1 --seconds 0.001` (process start, parse, one step).

Prints the load average it started at, then per ring and collision the user CPU time of each
of --repeats processes and their median. Never fails on time.

  bench/mesh_spawn_time.py [--rings 32x8,32x16,64x16,64x32,96x26] [--repeats 3]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BENCH = os.path.join(ROOT, "build", "devel", "lib", "flapsim", "flapsim_bench")
MESHES = os.path.join(ROOT, "test", "meshes")


def cpu_time(argv):
    """User CPU time (s) of one run of argv, which must succeed."""
    pid = os.fork()
    if pid == 0:
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.execv(argv[0], argv)
        finally:
            os._exit(127)
    _, status, usage = os.wait4(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"'{' '.join(argv)}' failed (exit {os.waitstatus_to_exitcode(status)})")
    return usage.ru_utime


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rings", default="32x8,32x16,64x16,64x32,96x26")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    rings = []
    for ring in args.rings.split(","):
        try:
            nu, nv = (int(x) for x in ring.split("x"))
        except ValueError:
            sys.exit(f"mesh_spawn_time.py: --rings: '{ring}' is not NUxNV")
        rings.append((nu, nv))
    if not os.access(BENCH, os.X_OK):
        sys.exit(f"mesh_spawn_time.py: no {os.path.relpath(BENCH, ROOT)}: build it")
    print("load average at the start: %.2f %.2f %.2f" % os.getloadavg(), flush=True)
    work = tempfile.mkdtemp(prefix="mesh_spawn_time")
    try:
        for nu, nv in rings:
            here = os.path.join(work, f"{nu}x{nv}")
            os.makedirs(here)
            subprocess.run([sys.executable, os.path.join(MESHES, "make_meshes.py"), "ring",
                            str(nu), str(nv), os.path.join(here, "ring.obj")], check=True)
            for collision in ("hull", "decomposed"):
                urdf = os.path.join(here, f"ring_{collision}.urdf")
                shutil.copy(os.path.join(MESHES, f"ring_{collision}.urdf"), urdf)
                times = [cpu_time([BENCH, "--urdf", urdf, "--runs", "1", "--seconds", "0.001"])
                         for _ in range(args.repeats)]
                print(f"ring {nu} x {nv} ({2 * nu * nv} triangles), {collision}: "
                      + " ".join(f"{t:.3f}" for t in times)
                      + f" s; median {statistics.median(times):.3f} s", flush=True)
    finally:
        shutil.rmtree(work)
    print("load average at the end: %.2f %.2f %.2f" % os.getloadavg())


if __name__ == "__main__":
    main()
