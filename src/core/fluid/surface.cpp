#include "fluid/surface.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "fluid/added_mass.h"
#include "fluid/box_union.h"
#include "fluid/mesh_surface.h"

namespace flapsim {

namespace {

// The cells of face f of a box (boxSurfaceCells' order: axis f / 2, sign + then -), nu x nv.
std::vector<SurfaceCell> faceCells(const Vec3& size, const Pose& origin, int f, int nu, int nv) {
  const int axis = f / 2;
  const double sign = f % 2 == 0 ? 1.0 : -1.0;
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const double cell_area = size[b] * size[c] / (nu * nv);
  Vec3 normal = Vec3::Zero();
  normal[axis] = sign;
  std::vector<SurfaceCell> cells;
  cells.reserve(static_cast<size_t>(nu * nv));
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      Vec3 p = Vec3::Zero();
      p[axis] = sign * 0.5 * size[axis];
      p[b] = size[b] * ((i + 0.5) / nu - 0.5);
      p[c] = size[c] * ((j + 0.5) / nv - 0.5);
      cells.push_back(SurfaceCell{origin.apply(p), origin.orientation * normal, cell_area});
    }
  }
  return cells;
}

}  // namespace

std::vector<SurfaceCell> boxSurfaceCells(const Vec3& size, const Pose& origin, int nu, int nv) {
  std::vector<SurfaceCell> cells;
  if (nu < 1 || nv < 1) return cells;
  cells.reserve(static_cast<size_t>(6 * nu * nv));
  for (int f = 0; f < 6; ++f) {
    const std::vector<SurfaceCell> face = faceCells(size, origin, f, nu, nv);
    cells.insert(cells.end(), face.begin(), face.end());
  }
  return cells;
}

namespace {

// A face's span and chord axes: `span` projected onto the face if enough of it lies in the
// face plane, else `longer_edge`; the chord normal x span and the face's extent along it.
void setFaceAxes(SurfaceFace& face, const Vec3& longer_edge, const std::optional<Vec3>& span) {
  face.span = longer_edge;
  if (span) {
    const Vec3 in_plane = *span - span->dot(face.normal) * face.normal;
    if (in_plane.norm() >= 0.1 * span->norm()) face.span = in_plane.normalized();
  }
  face.chord = face.normal.cross(face.span).normalized();
  face.chord_min = face.chord_max = face.corners[0].dot(face.chord);
  for (const Vec3& corner : face.corners) {
    face.chord_min = std::min(face.chord_min, corner.dot(face.chord));
    face.chord_max = std::max(face.chord_max, corner.dot(face.chord));
  }
}

// Makes `face` (to be appended to `surface`, all its cells kept) a regular grid of fu x fv cells
// `step_u`, `step_v` apart (body frame).
void setGrid(const AeroSurface& surface, SurfaceFace& face, int fu, int fv, const Vec3& step_u,
             const Vec3& step_v) {
  face.nu = fu;
  face.nv = fv;
  face.step_u = step_u;
  face.step_v = step_v;
  face.centre_x_normal = surface.cells[face.first_cell].centre.cross(face.normal);
  face.step_u_x_normal = face.step_u.cross(face.normal);
  face.step_v_x_normal = face.step_v.cross(face.normal);
  face.steps_of = static_cast<int>(surface.faces.size());
  for (size_t k = 0; k < surface.faces.size(); ++k) {
    const SurfaceFace& other = surface.faces[k];
    if (other.nu > 0 && other.step_u == face.step_u && other.step_v == face.step_v) {
      face.steps_of = static_cast<int>(k);
      break;
    }
  }
}

// Adds the faces of a box to `surface`, without the cells for which hidden(centre) holds: a
// face that keeps every cell is a regular grid, one that keeps some a plain list, one that
// keeps none is left out. With `thin_edges`, a face edge at most kThinEdge of the face's other
// edge (the rim of a plate) gets one row of cells: across it the flow does not change.
template <typename Hidden>
void addBoxFaces(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv,
                 const std::optional<Vec3>& span, bool thin_edges, Hidden hidden) {
  if (nu < 1 || nv < 1) return;
  constexpr double kThinEdge = 0.25;
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const double sign = f % 2 == 0 ? 1.0 : -1.0;
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    const int fu = thin_edges && size[b] <= kThinEdge * size[c] ? 1 : nu;
    const int fv = thin_edges && size[c] <= kThinEdge * size[b] ? 1 : nv;
    const std::vector<SurfaceCell> cells = faceCells(size, origin, f, fu, fv);
    SurfaceFace face;
    face.normal = cells.front().normal;
    for (int k = 0; k < 4; ++k) {
      Vec3 p = Vec3::Zero();
      p[axis] = sign * 0.5 * size[axis];
      p[b] = (k & 1 ? 0.5 : -0.5) * size[b];
      p[c] = (k & 2 ? 0.5 : -0.5) * size[c];
      face.corners[k] = origin.apply(p);
    }
    Vec3 edge = Vec3::Zero();
    edge[size[b] >= size[c] ? b : c] = 1.0;
    setFaceAxes(face, origin.orientation * edge, span);
    face.first_cell = static_cast<int>(surface.cells.size());
    for (const SurfaceCell& cell : cells) {
      if (!hidden(cell.centre)) surface.cells.push_back(cell);
    }
    face.cell_count = static_cast<int>(surface.cells.size()) - face.first_cell;
    if (face.cell_count == 0) continue;
    if (face.cell_count == fu * fv) {
      Vec3 step_u = Vec3::Zero(), step_v = Vec3::Zero();
      step_u[b] = size[b] / fu;
      step_v[c] = size[c] / fv;
      setGrid(surface, face, fu, fv, origin.orientation * step_u, origin.orientation * step_v);
    }
    surface.faces.push_back(face);
  }
}

// Whether p lies inside `box` or within `tolerance` of it.
bool insideBox(const Box& box, const Vec3& p, double tolerance) {
  return (inBox(box, p).cwiseAbs() - 0.5 * box.size).maxCoeff() <= tolerance;
}

// Whether p lies inside the cylinder or sphere `r` or within `tolerance` of it.
bool insideRound(const RoundShape& r, const Vec3& p, double tolerance) {
  const Vec3 q = r.origin.inverse().apply(p);
  if (r.kind == RoundShape::Kind::kSphere) return q.norm() <= r.radius + tolerance;
  return std::abs(q.z()) <= 0.5 * r.length + tolerance &&
         q.head<2>().norm() <= r.radius + tolerance;
}

// Adds one planar face of `cells` (all with normal `normal`, poses in the shape's frame
// `origin`) with corners `corners` (shape frame) and longer edge `edge`, minus the hidden cells.
template <typename Hidden>
void addPlainFace(AeroSurface& surface, const Pose& origin, const Vec3& normal,
                  const std::vector<SurfaceCell>& cells, const Vec3 (&corners)[4], const Vec3& edge,
                  const std::optional<Vec3>& span, Hidden hidden) {
  SurfaceFace face;
  face.normal = origin.orientation * normal;
  for (int k = 0; k < 4; ++k) face.corners[k] = origin.apply(corners[k]);
  setFaceAxes(face, origin.orientation * edge, span);
  face.first_cell = static_cast<int>(surface.cells.size());
  for (const SurfaceCell& c : cells) {
    const SurfaceCell cell{origin.apply(c.centre), face.normal, c.area};
    if (!hidden(cell.centre)) surface.cells.push_back(cell);
  }
  face.cell_count = static_cast<int>(surface.cells.size()) - face.first_cell;
  if (face.cell_count > 0) surface.faces.push_back(face);
}

// The faces of a cylinder: `around` flat strips of `along` cells on its side, and two caps of
// `around` sector cells; each cell has its share of the true area.
template <typename Hidden>
void addCylinderFaces(AeroSurface& surface, const RoundShape& r, int around, int along,
                      const std::optional<Vec3>& span, Hidden hidden) {
  const double step = 2.0 * M_PI / around, half = 0.5 * r.length;
  const double side_area = r.radius * step * r.length / along;
  for (int k = 0; k < around; ++k) {
    const double a0 = k * step, a1 = a0 + step, mid = a0 + 0.5 * step;
    const Vec3 n(std::cos(mid), std::sin(mid), 0.0);
    std::vector<SurfaceCell> cells;
    for (int j = 0; j < along; ++j) {
      const double z = r.length * ((j + 0.5) / along - 0.5);
      cells.push_back(SurfaceCell{r.radius * n + z * Vec3::UnitZ(), n, side_area});
    }
    const Vec3 p0(r.radius * std::cos(a0), r.radius * std::sin(a0), 0.0);
    const Vec3 p1(r.radius * std::cos(a1), r.radius * std::sin(a1), 0.0);
    const Vec3 corners[4] = {p0 - half * Vec3::UnitZ(), p1 - half * Vec3::UnitZ(),
                             p0 + half * Vec3::UnitZ(), p1 + half * Vec3::UnitZ()};
    const Vec3 edge = r.length >= (p1 - p0).norm() ? Vec3::UnitZ() : (p1 - p0).normalized();
    addPlainFace(surface, r.origin, n, cells, corners, edge, span, hidden);
  }
  // A sector's centroid lies 4 r sin(step / 2) / (3 step) from the axis.
  const double arm = 4.0 * r.radius * std::sin(0.5 * step) / (3.0 * step);
  for (const double sign : {1.0, -1.0}) {
    const Vec3 n = sign * Vec3::UnitZ();
    std::vector<SurfaceCell> cells;
    for (int k = 0; k < around; ++k) {
      const double mid = (k + 0.5) * step;
      const Vec3 c(arm * std::cos(mid), arm * std::sin(mid), sign * half);
      cells.push_back(SurfaceCell{c, n, M_PI * r.radius * r.radius / around});
    }
    const double q = r.radius;
    const Vec3 corners[4] = {Vec3(-q, -q, sign * half), Vec3(q, -q, sign * half),
                             Vec3(-q, q, sign * half), Vec3(q, q, sign * half)};
    addPlainFace(surface, r.origin, n, cells, corners, Vec3::UnitX(), span, hidden);
  }
}

// The faces of a sphere: `bands` bands of equal height (so of equal area, Archimedes) times
// `around` longitudes, one flat cell each, along the patch's mean normal, with the patch's
// true area. Its corners are its centre: the face is tested as a point.
template <typename Hidden>
void addSphereFaces(AeroSurface& surface, const RoundShape& r, int around, int bands,
                    const std::optional<Vec3>& span, Hidden hidden) {
  const double step = 2.0 * M_PI / around,
               area = 4.0 * M_PI * r.radius * r.radius / (bands * around);
  // The integral of sqrt(1 - z^2) dz (the horizontal part of the normal).
  auto ring = [](double z) {
    return 0.5 * (z * std::sqrt(std::max(0.0, 1.0 - z * z)) + std::asin(z));
  };
  for (int b = 0; b < bands; ++b) {
    const double z0 = -1.0 + 2.0 * b / bands, z1 = -1.0 + 2.0 * (b + 1) / bands;
    const double horizontal = (ring(z1) - ring(z0)) / (z1 - z0), vertical = 0.5 * (z0 + z1);
    for (int k = 0; k < around; ++k) {
      const double a0 = k * step, a1 = a0 + step;
      const double sine = (std::sin(a1) - std::sin(a0)) / step;
      const double cosine = (std::cos(a0) - std::cos(a1)) / step;
      const Vec3 n = Vec3(horizontal * sine, horizontal * cosine, vertical).normalized();
      const Vec3 c = r.radius * n;
      const Vec3 corners[4] = {c, c, c, c};
      const Vec3 east(-std::sin(a0 + 0.5 * step), std::cos(a0 + 0.5 * step), 0.0);
      addPlainFace(surface, r.origin, n, {SurfaceCell{c, n, area}}, corners, east, span, hidden);
    }
  }
}

// The faces of a mesh (meshFaces), minus the hidden cells; a rectangle that keeps all its cells
// is a regular grid.
template <typename Hidden>
void addMeshFaces(AeroSurface& surface, const MeshShape& m, int nu, int nv,
                  const std::optional<Vec3>& span, Hidden hidden) {
  for (const MeshFace& f : meshFaces(*m.mesh, nu, nv)) {
    SurfaceFace face;
    face.normal = m.origin.orientation * f.normal;
    for (int k = 0; k < 4; ++k) face.corners[k] = m.origin.apply(f.corners[k]);
    setFaceAxes(face, m.origin.orientation * f.edge, span);
    face.first_cell = static_cast<int>(surface.cells.size());
    for (const SurfaceCell& c : f.cells) {
      const SurfaceCell cell{m.origin.apply(c.centre), face.normal, c.area};
      if (!hidden(cell.centre)) surface.cells.push_back(cell);
    }
    face.cell_count = static_cast<int>(surface.cells.size()) - face.first_cell;
    if (face.cell_count == 0) continue;
    if (f.nu > 0 && face.cell_count == f.nu * f.nv) {
      setGrid(surface, face, f.nu, f.nv, m.origin.orientation * f.step_u,
              m.origin.orientation * f.step_v);
    }
    surface.faces.push_back(face);
  }
}

// The body-frame bounds of a mesh.
Eigen::AlignedBox3d meshBounds(const MeshShape& m) {
  Eigen::AlignedBox3d bounds;
  for (int k = 0; k < 8; ++k) {
    const MeshData& d = *m.mesh;
    bounds.extend(
        m.origin.apply(Vec3(k & 1 ? d.upper.x() : d.lower.x(), k & 2 ? d.upper.y() : d.lower.y(),
                            k & 4 ? d.upper.z() : d.lower.z())));
  }
  return bounds;
}

}  // namespace

int roundCellsAround(int nu) { return std::max(12, 3 * nu); }

int roundCellCount(const RoundShape& r, int nu, int nv) {
  const int around = roundCellsAround(nu);
  return r.kind == RoundShape::Kind::kSphere ? around * (around / 2)
                                             : around * (std::max(1, nv) + 2);
}

double roundVolume(const RoundShape& r) {
  const double area = M_PI * r.radius * r.radius;
  return r.kind == RoundShape::Kind::kSphere ? 4.0 / 3.0 * area * r.radius : area * r.length;
}

void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv) {
  addBoxFaces(surface, size, origin, nu, nv, std::nullopt, false,
              [](const Vec3&) { return false; });
  const double v = size.prod(), total = surface.volume + v;
  if (total > 0.0)
    surface.centroid = (surface.volume * surface.centroid + v * origin.position) / total;
  surface.volume = total;
}

AeroSurface buildSurface(const std::vector<Box>& boxes, int nu, int nv,
                         const std::optional<Vec3>& span, const std::vector<RoundShape>& rounds,
                         const std::vector<MeshShape>& meshes) {
  AeroSurface surface;
  double largest = 0.0;
  for (const Box& box : boxes) largest = std::max(largest, box.size.maxCoeff());
  for (const RoundShape& r : rounds) largest = std::max(largest, 2.0 * r.radius + r.length);
  for (const MeshShape& m : meshes) {
    largest = std::max(largest, (m.mesh->upper - m.mesh->lower).maxCoeff());
  }
  const double tolerance = 1e-6 * largest;
  // The shapes (boxes, round shapes, then meshes) whose bounds touch each shape's: only they can
  // hide its cells.
  std::vector<Eigen::AlignedBox3d> bounds;
  for (const Box& box : boxes) bounds.push_back(boxBounds(box));
  for (const RoundShape& r : rounds) {
    const Vec3 half =
        r.kind == RoundShape::Kind::kSphere
            ? Vec3::Constant(r.radius)
            : Vec3(r.origin.orientation.toRotationMatrix().col(2).cwiseAbs() * (0.5 * r.length) +
                   Vec3::Constant(r.radius));
    bounds.emplace_back(r.origin.position - half, r.origin.position + half);
  }
  for (const MeshShape& m : meshes) bounds.push_back(meshBounds(m));
  std::vector<std::vector<size_t>> near(bounds.size());
  for (const auto& [a, b] : overlappingBounds(bounds, -2.0 * tolerance)) {
    near[a].push_back(b);
    near[b].push_back(a);
  }
  const size_t first_mesh = boxes.size() + rounds.size();
  // Whether a cell centre of shape `shape` lies in another shape.
  auto hiddenFrom = [&](size_t shape) {
    return [&, shape](const Vec3& centre) {
      for (const size_t j : near[shape]) {
        if (j < boxes.size() ? insideBox(boxes[j], centre, tolerance)
            : j < first_mesh
                ? insideRound(rounds[j - boxes.size()], centre, tolerance)
                : insideMesh(*meshes[j - first_mesh].mesh,
                             meshes[j - first_mesh].origin.inverse().apply(centre), tolerance)) {
          return true;
        }
      }
      return false;
    };
  };
  for (size_t i = 0; i < boxes.size(); ++i) {
    addBoxFaces(surface, boxes[i].size, boxes[i].origin, nu, nv, span, true, hiddenFrom(i));
  }
  const BoxUnion u = unionOfBoxes(boxes);
  surface.volume = u.volume;
  surface.centroid = u.centroid;
  // Overlaps of round shapes and meshes with other shapes are counted twice (see the comment).
  auto addVolume = [&surface](double v, const Vec3& centroid) {
    const double total = surface.volume + v;
    if (total > 0.0) surface.centroid = (surface.volume * surface.centroid + v * centroid) / total;
    surface.volume = total;
  };
  const int around = roundCellsAround(nu);
  for (size_t i = 0; i < rounds.size(); ++i) {
    const RoundShape& r = rounds[i];
    if (r.kind == RoundShape::Kind::kSphere) {
      addSphereFaces(surface, r, around, around / 2, span, hiddenFrom(boxes.size() + i));
    } else {
      addCylinderFaces(surface, r, around, std::max(1, nv), span, hiddenFrom(boxes.size() + i));
    }
    addVolume(roundVolume(r), r.origin.position);
  }
  for (size_t i = 0; i < meshes.size(); ++i) {
    addMeshFaces(surface, meshes[i], nu, nv, span, hiddenFrom(first_mesh + i));
    addVolume(meshes[i].mesh->volume, meshes[i].origin.apply(meshes[i].mesh->centroid));
  }
  return surface;
}

namespace {

// The link's own boxes in its COM frame.
std::vector<Box> comFrameOwnBoxes(const LinkModel& link) {
  const Pose com_inv{-link.com, Quat::Identity()};
  std::vector<Box> boxes;
  for (const Box& b : link.boxes) boxes.push_back(Box{b.size, com_inv * b.origin});
  return boxes;
}

}  // namespace

std::vector<Box> comFrameBoxes(const LinkModel& link) {
  std::vector<Box> boxes = comFrameOwnBoxes(link);
  const Pose com_inv{-link.com, Quat::Identity()};
  for (const MeshShape& m : link.meshes) {
    const Vec3 size = m.mesh->upper - m.mesh->lower;
    Vec3 sorted = size;
    std::sort(sorted.data(), sorted.data() + 3);
    if (!(sorted[0] <= kPlateThickness * sorted[1])) continue;
    const Pose centre{m.origin.apply(0.5 * (m.mesh->upper + m.mesh->lower)), m.origin.orientation};
    boxes.push_back(Box{size, com_inv * centre});
  }
  return boxes;
}

std::vector<RoundShape> comFrameRounds(const LinkModel& link) {
  const Pose com_inv{-link.com, Quat::Identity()};
  std::vector<RoundShape> rounds = link.rounds;
  for (RoundShape& r : rounds) r.origin = com_inv * r.origin;
  return rounds;
}

std::vector<MeshShape> comFrameMeshes(const LinkModel& link) {
  const Pose com_inv{-link.com, Quat::Identity()};
  std::vector<MeshShape> meshes = link.meshes;
  for (MeshShape& m : meshes) m.origin = com_inv * m.origin;
  return meshes;
}

int subdivisionsU(const LinkModel& link, const AirParams& air) {
  return link.aero.subdivisions_u > 0 ? link.aero.subdivisions_u : air.subdivisions_u;
}

int subdivisionsV(const LinkModel& link, const AirParams& air) {
  return link.aero.subdivisions_v > 0 ? link.aero.subdivisions_v : air.subdivisions_v;
}

AeroSurface linkAeroSurface(const CreatureModel& model, int link, const AirParams& air) {
  const LinkModel& l = model.links.at(static_cast<size_t>(link));
  AeroSurface surface =
      buildSurface(comFrameOwnBoxes(l), subdivisionsU(l, air), subdivisionsV(l, air),
                   spanAxis(model, link), comFrameRounds(l), comFrameMeshes(l));
  surface.drag_coefficient =
      l.aero.drag_coefficient ? *l.aero.drag_coefficient : air.drag_coefficient;
  if (l.parent_joint >= 0) {
    for (int w : model.wing_joints) {
      if (model.joints[w].feather_joint == l.parent_joint) surface.pitch_axis_point = -l.com;
    }
  }
  return surface;
}

}  // namespace flapsim
