#!/usr/bin/env python3
"""Writes the test meshes of test_mesh.cpp and test_convex_decomposition.cpp (run from
anywhere; rewrites the files beside it).

Boxes as CAD programs export them (12 triangles, two per face, wound counter-clockwise seen
from outside), an icosphere, an open sheet, an inside-out box, a Collada box, a U-shaped
block and a ring (a torus of 2048 triangles). `make_meshes.py ring NU NV PATH` writes a ring of
NU x NV quads to PATH.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def box(sx, sy, sz):
    """Vertices and outward-wound triangles of a box centred at the origin."""
    verts = [(((i & 1) - 0.5) * sx, (((i >> 1) & 1) - 0.5) * sy, (((i >> 2) & 1) - 0.5) * sz)
             for i in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6),  # -z, +z
             (0, 1, 5, 4), (2, 6, 7, 3),  # -y, +y
             (0, 4, 6, 2), (1, 3, 7, 5)]  # -x, +x
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return verts, tris


def icosphere(radius, levels):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in verts]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(x + y) / 2 for x, y in zip(verts[a], verts[b])]
                n = math.sqrt(sum(x * x for x in p))
                verts.append(tuple(x / n for x in p))
                mid[key] = len(verts) - 1
            return mid[key]

        new = []
        for a, b, c in tris:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = new
    return [tuple(radius * x for x in p) for p in verts], tris


def u_block():
    """A U-shaped block (test_convex_decomposition): 0.1 m along x, 0.04 m along y, 0.06 m high
    (z from 0), its notch 0.04 m wide and 0.04 m deep (floor at z = 0.02), centred on x = 0.
    Its profile in the xz plane (counter-clockwise) extruded along y; each end cap is the
    profile's three rectangles (left prong, floor, right prong), two or three triangles each,
    so that no triangle spans the notch."""
    profile = [(-0.05, 0), (-0.02, 0), (0.02, 0), (0.05, 0), (0.05, 0.06), (0.02, 0.06),
               (0.02, 0.02), (-0.02, 0.02), (-0.02, 0.06), (-0.05, 0.06)]
    n = len(profile)
    verts = [(x, -0.02, z) for x, z in profile] + [(x, 0.02, z) for x, z in profile]
    tris = []
    for region in ([0, 1, 7, 8, 9], [1, 2, 6, 7], [3, 4, 5, 6, 2]):
        for k in range(1, len(region) - 1):
            a, b, c = region[0], region[k], region[k + 1]
            tris += [(a, b, c), (a + n, c + n, b + n)]  # front (-y) and back (+y) caps
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, i + n, j + n), (i, j + n, j)]  # the sides, outwards
    return verts, tris


def ring(nu, nv, radius=0.05, tube=0.015):
    """A torus about z (doc/urdf.md's decomposition timing): nu x nv quads of two triangles."""
    verts = []
    for i in range(nu):
        for j in range(nv):
            u, w = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            verts.append(((radius + tube * math.cos(w)) * math.cos(u),
                          (radius + tube * math.cos(w)) * math.sin(u), tube * math.sin(w)))
    tris = []
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j, ((i + 1) % nu) * nv + j
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            tris += [(a, b, c), (a, c, d)]
    return verts, tris


def write_stl(name, verts, tris):
    with open(os.path.join(HERE, name), "w") as f:
        f.write("solid %s\n" % name)
        for t in tris:
            a, b, c = (verts[i] for i in t)
            u = [b[k] - a[k] for k in range(3)]
            w = [c[k] - a[k] for k in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            length = math.sqrt(sum(x * x for x in n))
            f.write("  facet normal %.9g %.9g %.9g\n    outer loop\n" % tuple(x / length for x in n))
            for p in (a, b, c):
                f.write("      vertex %.9g %.9g %.9g\n" % p)
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid %s\n" % name)


def write_obj(name, verts, tris):
    with open(os.path.join(HERE, name), "w") as f:
        f.write("# %s\n" % name)
        for p in verts:
            f.write("v %.12g %.12g %.12g\n" % p)
        for t in tris:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


def write_dae(name, verts, tris):
    positions = " ".join("%.9g %.9g %.9g" % p for p in verts)
    indices = " ".join("%d %d %d" % t for t in tris)
    with open(os.path.join(HERE, name), "w") as f:
        f.write("""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="box" name="box"><mesh>
      <source id="box-pos"><float_array id="box-pos-array" count="%d">%s</float_array>
        <technique_common><accessor source="#box-pos-array" count="%d" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="box-vtx"><input semantic="POSITION" source="#box-pos"/></vertices>
      <triangles count="%d"><input semantic="VERTEX" source="#box-vtx" offset="0"/><p>%s</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="box-node"><instance_geometry url="#box"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
""" % (3 * len(verts), positions, len(verts), len(tris), indices))


def main():
    write_stl("plate_box.stl", *box(0.2, 0.2, 0.002))       # urdf/plate.urdf's box
    write_stl("wing_box.stl", *box(0.22, 0.35, 0.002))      # urdf/flap_unit.urdf's wing
    write_obj("body_box.obj", *box(0.08, 0.06, 0.03))       # urdf/flap_unit.urdf's body
    write_dae("cube.dae", *box(0.1, 0.1, 0.1))
    verts, tris = box(0.1, 0.1, 0.1)
    write_stl("inside_out_cube.stl", verts, [(a, c, b) for a, b, c in tris])
    write_stl("sheet.stl", [(-0.1, -0.1, 0), (0.1, -0.1, 0), (0.1, 0.1, 0), (-0.1, 0.1, 0)],
              [(0, 1, 2), (0, 2, 3)])
    write_obj("icosphere.obj", *icosphere(0.1, 3))
    write_obj("u_block.obj", *u_block())
    write_obj("ring.obj", *ring(64, 16))
    with open(os.path.join(HERE, "corrupt.stl"), "w") as f:
        f.write("solid broken\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0\n")


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "ring":  # make_meshes.py ring NU NV PATH
        write_obj(os.path.abspath(sys.argv[4]), *ring(int(sys.argv[2]), int(sys.argv[3])))
    else:
        main()
