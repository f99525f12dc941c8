#include "flapsim/air_model.h"

#include <algorithm>
#include <cmath>
#include <utility>

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
      face.nu = fu;
      face.nv = fv;
      Vec3 step = Vec3::Zero();
      step[b] = size[b] / fu;
      face.step_u = origin.orientation * step;
      step = Vec3::Zero();
      step[c] = size[c] / fv;
      face.step_v = origin.orientation * step;
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
    surface.faces.push_back(face);
  }
}

// p in the frame of box `box` (centre at the origin, edges along the axes).
Vec3 inBox(const Box& box, const Vec3& p) {
  return box.origin.orientation.conjugate() * (p - box.origin.position);
}

// Whether p lies inside `box` or within `tolerance` of it.
bool insideBox(const Box& box, const Vec3& p, double tolerance) {
  return (inBox(box, p).cwiseAbs() - 0.5 * box.size).maxCoeff() <= tolerance;
}

// The body-frame axis-aligned bounds of a box.
Eigen::AlignedBox3d bounds(const Box& box) {
  const Vec3 half = box.origin.orientation.toRotationMatrix().cwiseAbs() * (0.5 * box.size);
  return Eigen::AlignedBox3d(box.origin.position - half, box.origin.position + half);
}

// Whether `m` only permutes axes and flips their signs.
bool isSignedPermutation(const Eigen::Matrix3d& m) {
  for (int i = 0; i < 9; ++i) {
    const double a = std::abs(m.data()[i]);
    if (a > 1e-9 && std::abs(a - 1.0) > 1e-9) return false;
  }
  return true;
}

// Exact union of boxes that are axis-aligned in the frame `frame`: the coordinates of all
// their faces cut space into cuboids, each wholly inside some box or outside all of them.
BoxUnion alignedUnion(const std::vector<Box>& boxes, const Pose& frame) {
  const Eigen::Matrix3d to_frame = frame.orientation.conjugate().toRotationMatrix();
  std::vector<Vec3> lo, hi;
  std::vector<double> cuts[3];
  for (const Box& box : boxes) {
    const Vec3 centre = to_frame * (box.origin.position - frame.position);
    const Vec3 half =
        (to_frame * box.origin.orientation.toRotationMatrix()).cwiseAbs() * (0.5 * box.size);
    lo.push_back(centre - half);
    hi.push_back(centre + half);
    for (int a = 0; a < 3; ++a) {
      cuts[a].push_back(lo.back()[a]);
      cuts[a].push_back(hi.back()[a]);
    }
  }
  for (auto& c : cuts) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (size_t i = 0; i + 1 < cuts[0].size(); ++i) {
    for (size_t j = 0; j + 1 < cuts[1].size(); ++j) {
      for (size_t k = 0; k + 1 < cuts[2].size(); ++k) {
        const Vec3 a(cuts[0][i], cuts[1][j], cuts[2][k]);
        const Vec3 b(cuts[0][i + 1], cuts[1][j + 1], cuts[2][k + 1]);
        const Vec3 mid = 0.5 * (a + b);
        bool inside = false;
        for (size_t n = 0; n < boxes.size() && !inside; ++n) {
          inside = (mid.array() > lo[n].array()).all() && (mid.array() < hi[n].array()).all();
        }
        if (!inside) continue;
        const double v = (b - a).prod();
        volume += v;
        moment += v * mid;
      }
    }
  }
  BoxUnion u;
  u.volume = volume;
  if (volume > 0.0) u.centroid = frame.apply(moment / volume);
  return u;
}

constexpr int kUnionLines = 128;  // per edge of the face of a box that overlaps an earlier one

}  // namespace

BoxUnion unionOfBoxes(const std::vector<Box>& boxes) {
  BoxUnion u;
  if (boxes.empty()) return u;
  bool aligned = true;
  const Eigen::Matrix3d first = boxes[0].origin.orientation.conjugate().toRotationMatrix();
  for (const Box& box : boxes) {
    aligned = aligned && isSignedPermutation(first * box.origin.orientation.toRotationMatrix());
  }
  if (aligned) return alignedUnion(boxes, boxes[0].origin);
  // Each box adds the part of it that no earlier box holds: all of it unless their bounds
  // overlap, else what lines through it along one edge find (below).
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& box = boxes[i];
    std::vector<const Box*> earlier;
    for (size_t j = 0; j < i; ++j) {
      if (!bounds(box).intersection(bounds(boxes[j])).isEmpty()) earlier.push_back(&boxes[j]);
    }
    if (earlier.empty()) {
      volume += box.size.prod();
      moment += box.size.prod() * box.origin.position;
      continue;
    }
    // Along lines parallel to the box's x edge, on an n x n grid over its y-z face, the
    // earlier boxes cover intervals found exactly; only the grid over the face is discrete.
    const int n = kUnionLines;
    const double dx = box.size.x(), area = box.size.y() * box.size.z() / (n * n);
    const Vec3 along = box.origin.orientation * Vec3::UnitX();
    std::vector<std::pair<double, double>> covered;
    for (int b = 0; b < n; ++b) {
      for (int c = 0; c < n; ++c) {
        const Vec3 mid = box.origin.apply(
            Vec3(0.0, box.size.y() * ((b + 0.5) / n - 0.5), box.size.z() * ((c + 0.5) / n - 0.5)));
        covered.clear();
        for (const Box* other : earlier) {
          double t0 = -0.5 * dx, t1 = 0.5 * dx;
          const Vec3 o = inBox(*other, mid);
          const Vec3 d = other->origin.orientation.conjugate() * along;
          for (int k = 0; k < 3 && t0 < t1; ++k) {
            const double half = 0.5 * other->size[k];
            if (std::abs(d[k]) < 1e-15) {
              if (std::abs(o[k]) > half) t1 = t0;
              continue;
            }
            const double ta = (-half - o[k]) / d[k], tb = (half - o[k]) / d[k];
            t0 = std::max(t0, std::min(ta, tb));
            t1 = std::min(t1, std::max(ta, tb));
          }
          if (t0 < t1) covered.emplace_back(t0, t1);
        }
        std::sort(covered.begin(), covered.end());
        // What is left of the line [-dx/2, dx/2]: its length and first moment in t.
        double length = dx, first_moment = 0.0, end = -0.5 * dx;
        for (const auto& [t0, t1] : covered) {
          const double from = std::max(t0, end);
          if (t1 <= from) continue;
          length -= t1 - from;
          first_moment -= 0.5 * (t1 * t1 - from * from);
          end = t1;
        }
        volume += area * length;
        moment += area * (length * mid + first_moment * along);
      }
    }
  }
  u.volume = volume;
  if (volume > 0.0) u.centroid = moment / volume;
  return u;
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
                         const std::optional<Vec3>& span) {
  AeroSurface surface;
  double largest = 0.0;
  for (const Box& box : boxes) largest = std::max(largest, box.size.maxCoeff());
  const double tolerance = 1e-6 * largest;
  for (size_t i = 0; i < boxes.size(); ++i) {
    auto hidden = [&](const Vec3& centre) {
      for (size_t j = 0; j < boxes.size(); ++j) {
        if (j != i && insideBox(boxes[j], centre, tolerance)) return true;
      }
      return false;
    };
    addBoxFaces(surface, boxes[i].size, boxes[i].origin, nu, nv, span, true, hidden);
  }
  const BoxUnion u = unionOfBoxes(boxes);
  surface.volume = u.volume;
  surface.centroid = u.centroid;
  return surface;
}

std::vector<Box> comFrameBoxes(const LinkModel& link) {
  const Pose com_inv{-link.com, Quat::Identity()};
  std::vector<Box> boxes;
  for (const Box& b : link.boxes) boxes.push_back(Box{b.size, com_inv * b.origin});
  return boxes;
}

int subdivisionsU(const LinkModel& link, const AirParams& air) {
  return link.aero.subdivisions_u > 0 ? link.aero.subdivisions_u : air.subdivisions_u;
}

int subdivisionsV(const LinkModel& link, const AirParams& air) {
  return link.aero.subdivisions_v > 0 ? link.aero.subdivisions_v : air.subdivisions_v;
}

AeroSurface linkAeroSurface(const CreatureModel& model, int link, const AirParams& air) {
  const LinkModel& l = model.links.at(static_cast<size_t>(link));
  AeroSurface surface = buildSurface(comFrameBoxes(l), subdivisionsU(l, air), subdivisionsV(l, air),
                                     spanAxis(model, link));
  surface.drag_coefficient =
      l.aero.drag_coefficient ? *l.aero.drag_coefficient : air.drag_coefficient;
  if (l.parent_joint >= 0) {
    for (int w : model.wing_joints) {
      if (model.joints[w].feather_joint == l.parent_joint) surface.pitch_axis_point = -l.com;
    }
  }
  return surface;
}

Wrench buoyancyWrench(const AeroSurface& surface, const BodyKinematics& body, double density,
                      const Vec3& gravity) {
  const Vec3 force = buoyancyForce(surface.volume, density, gravity);
  const Vec3 centroid =
      body.has_body_frame ? body.rotation * surface.centroid : body.orientation * surface.centroid;
  return Wrench{force, centroid.cross(force)};
}

namespace {

// The air's motion seen from a body: velocities in the body frame, where cell centres and
// normals are constant.
struct BodyFlow {
  BodyFlow(const BodyKinematics& body, const AirParams& air)
      : rot(body.has_body_frame ? body.rotation : body.orientation.toRotationMatrix()),
        v(body.has_body_frame ? body.body_linear_velocity : rot.transpose() * body.linear_velocity),
        w(body.has_body_frame ? body.body_angular_velocity
                              : rot.transpose() * body.angular_velocity),
        wind(air.wind.isZero(0.0) ? Vec3::Zero() : Vec3(rot.transpose() * air.wind)) {}

  Vec3 at(const Vec3& point) const { return relativeAirVelocity(v, w, point, wind); }
  // u.n is affine over a face: if no corner advances into the air, no cell does.
  bool advances(const SurfaceFace& face) const {
    for (const Vec3& corner : face.corners) {
      if (at(corner).dot(face.normal) > 0.0) return true;
    }
    return false;
  }

  Eigen::Matrix3d rot;
  Vec3 v, w, wind;
};

// Sums per-cell forces of `force(u, cell, span)` over a body, skipping retreating faces.
template <typename CellForce>
Wrench sumCells(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                std::vector<Vec3>* cell_forces, CellForce force) {
  const BodyFlow flow(body, air);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  auto cellRange = [&](int first, int count, const Vec3& span) {
    for (int i = first; i < first + count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 f = force(flow.at(cell.centre), cell, span);
      if (f.isZero(0.0)) continue;
      total += f;
      torque += cell.centre.cross(f);
      if (cell_forces) (*cell_forces)[i] = flow.rot * f;
    }
  };
  if (surface.faces.empty()) {
    cellRange(0, static_cast<int>(surface.cells.size()), Vec3::Zero());
  } else {
    for (const SurfaceFace& face : surface.faces) {
      if (flow.advances(face)) cellRange(face.first_cell, face.cell_count, face.span);
    }
  }
  return Wrench{flow.rot * total, flow.rot * torque};
}

constexpr double kDeg = M_PI / 180.0;

// u.n and |u|^2 over a grid face's cells (a, b) as polynomials in the cell indices (see
// PressureAirModel::bodyWrench): u.n = n0 + a n_a + b n_b, |u|^2 = q00 + a q0a + b q0b +
// a^2 qaa + a b qab + b^2 qbb.
struct GridAxes {
  double n0, n_a, n_b;
  double q00, q0a, q0b, qaa, qab, qbb;
};

// Sums over the cells of |u| max(u.n, 0) (the pressure without its constant factor), and
// of it times a and times b.
struct GridSums {
  double sum = 0.0, across = 0.0, along = 0.0;
};

// Two cells of a row at a time, in the two lanes of a SIMD register (square roots too); a
// lane past the row's end is weighted zero. kRows and kCols, when not 0, are rows and cols
// known at compile time (the usual grids: the loops unroll).
template <int kRows, int kCols>
GridSums gridSums(const GridAxes& g, int rows_in, int cols_in) {
  using Pair = Eigen::Array2d;
  const int rows = kRows > 0 ? kRows : rows_in, cols = kCols > 0 ? kCols : cols_in;
  const Pair step(0.0, 1.0), last(1.0, cols % 2 == 0 ? 1.0 : 0.0);
  Pair sum = Pair::Zero(), across = Pair::Zero(), along = Pair::Zero();
  for (int a = 0; a < rows; ++a) {
    const double un_a = g.n0 + a * g.n_a;
    const double q_a = g.q00 + a * (g.q0a + a * g.qaa), q_ab = g.q0b + a * g.qab;
    Pair row = Pair::Zero(), row_b = Pair::Zero();
    for (int b0 = 0; b0 < cols; b0 += 2) {
      const Pair b = step + static_cast<double>(b0);
      const Pair un = (un_a + b * g.n_b).max(0.0);
      Pair p = (q_a + b * (q_ab + b * g.qbb)).max(0.0).sqrt() * un;
      if (b0 + 2 > cols) p *= last;
      row += p;
      row_b += p * b;
    }
    sum += row;
    across += static_cast<double>(a) * row;
    along += row_b;
  }
  return GridSums{sum.sum(), across.sum(), along.sum()};
}

// A 4 x 4 grid (a box's face): two rows at a time instead, in the lanes (a, a + 1), which
// broadcasts per column what gridSums broadcasts per row. The same cells, summed in another
// order.
GridSums gridSums4x4(const GridAxes& g) {
  using Pair = Eigen::Array2d;
  Pair sum = Pair::Zero(), across = Pair::Zero(), along = Pair::Zero();
  for (int a0 = 0; a0 < 4; a0 += 2) {
    const Pair a = Pair(0.0, 1.0) + static_cast<double>(a0);
    const Pair un_a = g.n0 + a * g.n_a;
    const Pair q_a = g.q00 + a * (g.q0a + a * g.qaa), q_ab = g.q0b + a * g.qab;
    Pair row = Pair::Zero(), row_b = Pair::Zero();
    for (int j = 0; j < 4; ++j) {
      const double b = j;
      const Pair un = (un_a + b * g.n_b).max(0.0);
      const Pair p = (q_a + b * (q_ab + b * g.qbb)).max(0.0).sqrt() * un;
      row += p;
      row_b += p * b;
    }
    sum += row;
    across += a * row;
    along += row_b;
  }
  return GridSums{sum.sum(), across.sum(), along.sum()};
}

GridSums gridSums(const GridAxes& g, int rows, int cols) {
  if (cols == 4) {
    if (rows == 4) return gridSums4x4(g);
    if (rows == 1) return gridSums<1, 4>(g, rows, cols);
    return gridSums<0, 4>(g, rows, cols);
  }
  return gridSums<0, 0>(g, rows, cols);
}

// The forces on row i of grid face `face` (see PressureAirModel::bodyWrench), world frame.
void recordRow(const SurfaceFace& face, int i, double un_i, double n_j, double k, double q_i,
               double q_ij, double qjj, const Eigen::Matrix3d& rot, std::vector<Vec3>& out) {
  for (int j = 0; j < face.nv; ++j) {
    const double un = un_i + j * n_j;
    if (un <= 0.0) continue;
    const double p = k * std::sqrt(std::max(0.0, q_i + j * (q_ij + j * qjj))) * un;
    out[face.first_cell + i * face.nv + j] = rot * (-p * face.normal);
  }
}

}  // namespace

Wrench PressureAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                    const AirParams& air, std::vector<Vec3>* cell_forces) const {
  const double cd = surface.drag_coefficient;
  if (surface.faces.empty()) {
    return sumCells(body, surface, air, cell_forces,
                    [&](const Vec3& u, const SurfaceCell& cell, const Vec3&) {
                      return pressureForce(u, cell.normal, cell.area, air.density, cd);
                    });
  }
  // Per face: every force is along the face's normal n, so the face's force is -(sum p_i) n
  // and its torque -(sum p_i c_i) x n; only magnitudes are summed per cell.
  const BodyFlow flow(body, air);
  const Vec3 drift = flow.v - flow.wind;  // the air's velocity relative to the COM
  const double half_rho_cd = 0.5 * air.density * cd;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  // The cell steps' velocity terms of the last grid computed, shared by faces with the same
  // steps (a box's opposite faces).
  int steps_of = -1;
  Vec3 du = Vec3::Zero(), dv = Vec3::Zero();
  double qii = 0.0, qij = 0.0, qjj = 0.0;
  for (const SurfaceFace& face : surface.faces) {
    if (face.nu > 0) {
      // On a grid the relative velocity is affine in the cell index (u(c + s) = u(c) + w x s),
      // and so is the centre: sum p, p i and p j, not vectors. Then u.n is affine in (i, j)
      // and |u|^2 a quadratic: a cell costs a few multiply-adds and one square root.
      const Vec3& n = face.normal;
      // u.n = v.n + (w x r).n = v.n + w.(r x n): no cross product before the test below.
      const double n0 = drift.dot(n) + flow.w.dot(face.centre_x_normal);
      const double n_i = flow.w.dot(face.step_u_x_normal), n_j = flow.w.dot(face.step_v_x_normal);
      // The largest u.n over the cell centres: if none advances into the air, none is pushed.
      if (n0 + std::max(0.0, (face.nu - 1) * n_i) + std::max(0.0, (face.nv - 1) * n_j) <= 0.0) {
        continue;
      }
      const SurfaceCell& first = surface.cells[face.first_cell];
      const Vec3 u0 = flow.at(first.centre);
      if (face.steps_of != steps_of) {
        du = flow.w.cross(face.step_u);
        dv = flow.w.cross(face.step_v);
        qii = du.squaredNorm();
        qij = 2.0 * du.dot(dv);
        qjj = dv.squaredNorm();
        steps_of = face.steps_of;
      }
      const double k = half_rho_cd * first.area;
      const double q00 = u0.squaredNorm(), q0i = 2.0 * u0.dot(du), q0j = 2.0 * u0.dot(dv);
      // Vectors run along the longer edge of the grid (a plate's rim is one cell wide).
      GridSums g;
      if (face.nv >= face.nu) {
        g = gridSums(GridAxes{n0, n_i, n_j, q00, q0i, q0j, qii, qij, qjj}, face.nu, face.nv);
      } else {
        g = gridSums(GridAxes{n0, n_j, n_i, q00, q0j, q0i, qjj, qij, qii}, face.nv, face.nu);
        std::swap(g.across, g.along);
      }
      if (cell_forces) {
        for (int i = 0; i < face.nu; ++i) {
          recordRow(face, i, n0 + i * n_i, n_j, k, q00 + i * (q0i + i * qii), q0j + i * qij, qjj,
                    flow.rot, *cell_forces);
        }
      }
      // The torque -(sum c_i p_i) x n from the centres' cross products with n.
      const double p = k * g.sum;
      force -= p * n;
      torque -= p * face.centre_x_normal + (k * g.across) * face.step_u_x_normal +
                (k * g.along) * face.step_v_x_normal;
      continue;
    }
    if (!flow.advances(face)) continue;
    double sum = 0.0;
    Vec3 moment = Vec3::Zero();
    for (int i = face.first_cell; i < face.first_cell + face.cell_count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const double p =
          pressureMagnitude(flow.at(cell.centre), face.normal, cell.area, air.density, cd);
      sum += p;
      moment += p * cell.centre;
      if (cell_forces) (*cell_forces)[i] = flow.rot * (-p * face.normal);
    }
    force -= sum * face.normal;
    torque -= moment.cross(face.normal);
  }
  return Wrench{flow.rot * force, flow.rot * torque};
}

double angleOfAttack(const Vec3& u, const Vec3& n) {
  const double speed = u.norm();
  if (speed == 0.0) return 0.0;
  return std::asin(std::min(1.0, std::abs(u.dot(n)) / speed)) / kDeg;
}

double liftCoefficient(double a, const QuasiSteadyCoefficients& c) {
  return c.lift_mean + c.lift_amplitude * std::sin((c.lift_frequency * a + c.lift_phase) * kDeg);
}

double dragCoefficient(double a, const QuasiSteadyCoefficients& c) {
  return c.drag_mean - c.drag_amplitude * std::cos((c.drag_frequency * a + c.drag_phase) * kDeg);
}

namespace {

// quasiSteadyForce, and the angle of attack in degrees in *alpha_deg when the force is not
// zero.
Vec3 quasiSteadyForceAt(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                        const QuasiSteadyCoefficients& c, double* alpha_deg) {
  // Edge-on within rounding counts as edge-on: C_D(0) > 0 would otherwise give a full
  // face's drag to whichever face rounding happens to tilt forward.
  if (u.dot(n) <= 1e-12 * u.norm()) return Vec3::Zero();
  const Vec3 chordwise = u - u.dot(span) * span;
  const double speed2 = chordwise.squaredNorm();
  if (speed2 == 0.0) return Vec3::Zero();
  const Vec3 drag_dir = -chordwise / std::sqrt(speed2);
  const double alpha = angleOfAttack(chordwise, n);
  *alpha_deg = alpha;
  const double q = 0.5 * density * area * speed2;
  Vec3 force = q * dragCoefficient(alpha, c) * drag_dir;
  Vec3 lift_dir = -n - (-n).dot(drag_dir) * drag_dir;  // -n without its part along the flow
  lift_dir -= lift_dir.dot(span) * span;
  const double norm = lift_dir.norm();
  if (norm > 1e-12) force += q * liftCoefficient(alpha, c) * (lift_dir / norm);
  return force;
}

}  // namespace

Vec3 quasiSteadyForce(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                      const QuasiSteadyCoefficients& c) {
  double alpha = 0.0;
  return quasiSteadyForceAt(u, n, span, area, density, c, &alpha);
}

double centreOfPressureFraction(double alpha_deg) {
  return 0.82 * std::abs(alpha_deg) / 180.0 + 0.05;
}

double rotationalLiftCoefficient(double x0) { return M_PI * (0.75 - x0); }

Wrench QuasiSteadyAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                       const AirParams& air, std::vector<Vec3>* cell_forces) const {
  if (surface.faces.empty()) {
    return sumCells(body, surface, air, cell_forces,
                    [&](const Vec3& u, const SurfaceCell& cell, const Vec3& span) {
                      return quasiSteadyForce(u, cell.normal, span, cell.area, air.density,
                                              air.quasi_steady);
                    });
  }
  const BodyFlow flow(body, air);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  for (const SurfaceFace& face : surface.faces) {
    if (!flow.advances(face)) continue;
    const Vec3 &n = face.normal, &s = face.span, &e = face.chord;
    const double chord = face.chord_max - face.chord_min;
    const double axis = surface.pitch_axis_point.dot(e);  // the pitch axis' chord coordinate
    // Turning about n x e raises the angle of attack of this face when it advances towards +e
    // (and lowers it towards -e).
    const double spin = flow.w.dot(n.cross(e));
    const bool rotational = air.rotational_lift && chord > 0.0 && spin != 0.0;
    for (int i = face.first_cell; i < face.first_cell + face.cell_count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 u = flow.at(cell.centre);
      double alpha = 0.0;
      Vec3 f = quasiSteadyForceAt(u, n, s, cell.area, air.density, air.quasi_steady, &alpha);
      if (f.isZero(0.0)) continue;
      Vec3 at = cell.centre;
      if (air.centre_of_pressure_shift && chord > 0.0) {
        const Vec3 chordwise = u - u.dot(s) * s;
        const double ahead = chordwise.dot(e);  // > 0: the leading edge is on the +e side
        if (ahead != 0.0) {
          at += (0.5 - centreOfPressureFraction(alpha)) * chord * std::copysign(1.0, ahead) * e;
        }
      }
      torque += at.cross(f);
      if (rotational) {
        // The strip's motion at the pitch axis: its speed U, and its leading edge.
        const Vec3 p = cell.centre + (axis - cell.centre.dot(e)) * e;
        Vec3 up = flow.at(p);
        up -= up.dot(s) * s;
        const double ahead = up.dot(e);
        if (ahead != 0.0) {
          const double sign = std::copysign(1.0, ahead);
          const double x0 =
              sign > 0.0 ? (face.chord_max - axis) / chord : (axis - face.chord_min) / chord;
          const Vec3 rot = -rotationalLiftCoefficient(x0) * air.density * up.norm() * chord *
                           cell.area * sign * spin * n;
          f += rot;
          torque += cell.centre.cross(rot);
        }
      }
      total += f;
      if (cell_forces) (*cell_forces)[i] = flow.rot * f;
    }
  }
  return Wrench{flow.rot * total, flow.rot * torque};
}

AirModelPtr makeAirModel(const std::string& name) {
  if (name == "pressure") return std::make_shared<PressureAirModel>();
  if (name == "quasi_steady") return std::make_shared<QuasiSteadyAirModel>();
  return nullptr;
}

}  // namespace flapsim
