#include "fluid/mesh_surface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace flapsim {

namespace {

using Triangle = std::array<int, 3>;

Vec3 unitNormal(const MeshData& m, const Triangle& t) {
  const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
  return (b - a).cross(c - a).normalized();
}

// The corner of triangle t opposite its longest edge (0, 1 or 2).
int rightCorner(const MeshData& m, const Triangle& t) {
  int corner = 0;
  double longest = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double l = (m.vertices[t[(k + 1) % 3]] - m.vertices[t[(k + 2) % 3]]).squaredNorm();
    if (l > longest) {
      longest = l;
      corner = k;
    }
  }
  return corner;
}

// The rectangle of triangles t and u if they make one (see meshFaces): its corner at t's
// right angle, and its two edges from there; false if not.
bool rectangle(const MeshData& m, const Triangle& t, const Triangle& u, Vec3& corner, Vec3& e1,
               Vec3& e2) {
  const int k = rightCorner(m, t), l = rightCorner(m, u);
  const int a = t[(k + 1) % 3], b = t[(k + 2) % 3];
  // u runs the shared longest edge the other way: b -> a.
  if (u[(l + 1) % 3] != b || u[(l + 2) % 3] != a) return false;
  const Vec3 &c = m.vertices[t[k]], &d = m.vertices[u[l]];
  e1 = m.vertices[a] - c;
  e2 = m.vertices[b] - c;
  const double scale = e1.norm() * e2.norm();
  if (std::abs(e1.dot(e2)) > 1e-9 * scale) return false;
  if ((d - (c + e1 + e2)).norm() > 1e-9 * std::sqrt(scale)) return false;
  if (unitNormal(m, t).dot(unitNormal(m, u)) < 1.0 - 1e-12) return false;
  corner = c;
  return true;
}

// A rectangle face (corner, edges e1, e2 with e1 x e2 outward), nu x nv cells as a box face.
MeshFace rectangleFace(const Vec3& corner, Vec3 e1, Vec3 e2, int nu, int nv) {
  MeshFace f;
  f.normal = e1.cross(e2).normalized();
  int axis = 0;
  f.normal.cwiseAbs().maxCoeff(&axis);
  const int after = (axis + 1) % 3;
  // e_u: the edge nearer the axis after the normal's; e_u x e_v along the normal or not.
  Vec3 eu = e1, ev = e2;
  if (std::abs(e2.normalized()[after]) > std::abs(e1.normalized()[after])) std::swap(eu, ev);
  constexpr double kThinEdge = 0.25;
  const double lu = eu.norm(), lv = ev.norm();
  const int fu = lu <= kThinEdge * lv ? 1 : nu, fv = lv <= kThinEdge * lu ? 1 : nv;
  f.nu = fu;
  f.nv = fv;
  f.step_u = eu / fu;
  f.step_v = ev / fv;
  for (int k = 0; k < 4; ++k)
    f.corners[k] = corner + (k & 1 ? eu : Vec3(0, 0, 0)) + (k & 2 ? ev : Vec3(0, 0, 0));
  f.edge = (lu >= lv ? eu : ev).normalized();
  const double area = lu * lv / (fu * fv);
  for (int i = 0; i < fu; ++i) {
    for (int j = 0; j < fv; ++j) {
      const Vec3 centre = corner + (i + 0.5) * f.step_u + (j + 0.5) * f.step_v;
      f.cells.push_back(SurfaceCell{centre, f.normal, area});
    }
  }
  return f;
}

// A triangle face of k x k equal cells.
MeshFace triangleFace(const MeshData& m, const Triangle& t, double h) {
  MeshFace f;
  const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
  const Vec3 ab = b - a, ac = c - a;
  f.normal = ab.cross(ac).normalized();
  f.corners[0] = a;
  f.corners[1] = b;
  f.corners[2] = f.corners[3] = c;
  const int r = rightCorner(m, t);
  const double longest = (m.vertices[t[(r + 2) % 3]] - m.vertices[t[(r + 1) % 3]]).norm();
  f.edge = (m.vertices[t[(r + 2) % 3]] - m.vertices[t[(r + 1) % 3]]) / longest;
  const int k = std::clamp(static_cast<int>(std::ceil(longest / h - 1e-9)), 1, 8);
  const double area = 0.5 * ab.cross(ac).norm() / (k * k);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; i + j < k; ++j) {
      // The cell (i, j) with its corner at the origin, and the one turned over beside it.
      f.cells.push_back(
          SurfaceCell{a + ((i + 1.0 / 3) * ab + (j + 1.0 / 3) * ac) / k, f.normal, area});
      if (i + j + 1 < k) {
        f.cells.push_back(
            SurfaceCell{a + ((i + 2.0 / 3) * ab + (j + 2.0 / 3) * ac) / k, f.normal, area});
      }
    }
  }
  return f;
}

}  // namespace

std::vector<MeshFace> meshFaces(const MeshData& m, int nu, int nv) {
  std::vector<MeshFace> faces;
  if (nu < 1 || nv < 1) return faces;
  const double h = (m.upper - m.lower).maxCoeff() / std::max(nu, nv);
  // The triangles on each undirected edge.
  std::map<std::pair<int, int>, std::vector<int>> on_edge;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      on_edge[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(i));
    }
  }
  std::vector<bool> done(m.triangles.size(), false);
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    if (done[i]) continue;
    const Triangle& t = m.triangles[i];
    const int k = rightCorner(m, t);
    const int a = t[(k + 1) % 3], b = t[(k + 2) % 3];
    const std::vector<int>& pair = on_edge[{std::min(a, b), std::max(a, b)}];
    Vec3 corner, e1, e2;
    if (pair.size() == 2) {
      const int j = pair[0] == static_cast<int>(i) ? pair[1] : pair[0];
      if (!done[j] && rectangle(m, t, m.triangles[j], corner, e1, e2)) {
        done[i] = done[j] = true;
        faces.push_back(rectangleFace(corner, e1, e2, nu, nv));
        continue;
      }
    }
    done[i] = true;
    faces.push_back(triangleFace(m, t, h));
  }
  return faces;
}

int meshCellCount(const MeshData& mesh, int nu, int nv) {
  int cells = 0;
  for (const MeshFace& f : meshFaces(mesh, nu, nv)) cells += static_cast<int>(f.cells.size());
  return cells;
}

namespace {

// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

bool insideMesh(const MeshData& m, const Vec3& p, double tolerance) {
  if (((m.lower - p).array() > tolerance).any() || ((p - m.upper).array() > tolerance).any()) {
    return false;
  }
  double solid_angle = 0.0;
  for (const Triangle& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    if ((nearestOnTriangle(p, a, b, c) - p).norm() <= tolerance) return true;
    // Van Oosterom and Strackee: tan(omega / 2) of the triangle seen from p.
    const Vec3 x = a - p, y = b - p, z = c - p;
    const double lx = x.norm(), ly = y.norm(), lz = z.norm();
    const double num = x.dot(y.cross(z));
    const double den = lx * ly * lz + x.dot(y) * lz + x.dot(z) * ly + y.dot(z) * lx;
    solid_angle += 2.0 * std::atan2(num, den);
  }
  return m.closed && std::abs(solid_angle) > 2.0 * M_PI;
}

}  // namespace flapsim
