#include "fluid/box_union.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace flapsim {

namespace {

// A volume and its first moment about the body origin.
struct VolumeMoment {
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
};

// Whether `m` only permutes axes and flips their signs.
bool isSignedPermutation(const Eigen::Matrix3d& m) {
  for (int i = 0; i < 9; ++i) {
    const double a = std::abs(m.data()[i]);
    if (a > 1e-9 && std::abs(a - 1.0) > 1e-9) return false;
  }
  return true;
}

// The covered length and first moment of a set of intervals on a line, kept under insertions
// and removals of intervals between the points `cuts` (a segment tree over them).
class CoverTree {
 public:
  explicit CoverTree(std::vector<double> cuts) : cuts_(std::move(cuts)) {
    const size_t n = cuts_.size() < 2 ? 1 : cuts_.size() - 1;
    count_.assign(4 * n, 0);
    length_.assign(4 * n, 0.0);
    moment_.assign(4 * n, 0.0);
  }
  // Adds (delta 1) or removes (-1) the interval [from, to], both among the cuts.
  void change(double from, double to, int delta) {
    const size_t a = index(from), b = index(to);
    if (a < b) change(1, 0, cuts_.size() - 1, a, b, delta);
  }
  double length() const { return length_[1]; }
  double moment() const { return moment_[1]; }

 private:
  size_t index(double x) const {
    return static_cast<size_t>(std::lower_bound(cuts_.begin(), cuts_.end(), x) - cuts_.begin());
  }
  void change(size_t node, size_t lo, size_t hi, size_t a, size_t b, int delta) {
    if (b <= lo || hi <= a) return;
    if (a <= lo && hi <= b) {
      count_[node] += delta;
    } else {
      const size_t mid = (lo + hi) / 2;
      change(2 * node, lo, mid, a, b, delta);
      change(2 * node + 1, mid, hi, a, b, delta);
    }
    if (count_[node] > 0) {
      length_[node] = cuts_[hi] - cuts_[lo];
      moment_[node] = 0.5 * (cuts_[hi] * cuts_[hi] - cuts_[lo] * cuts_[lo]);
    } else if (hi - lo == 1) {
      length_[node] = moment_[node] = 0.0;
    } else {
      length_[node] = length_[2 * node] + length_[2 * node + 1];
      moment_[node] = moment_[2 * node] + moment_[2 * node + 1];
    }
  }
  std::vector<double> cuts_;
  std::vector<int> count_;
  std::vector<double> length_, moment_;
};

// The area of a union of rectangles [lo, hi] in the plane and its first moments.
struct AreaMoments {
  double area = 0.0, first_y = 0.0, first_z = 0.0;
};

AreaMoments rectangleUnion(const std::vector<Eigen::Vector2d>& lo,
                           const std::vector<Eigen::Vector2d>& hi) {
  AreaMoments out;
  std::vector<double> zs;
  struct Edge {
    double y;
    int delta;
    size_t rect;
  };
  std::vector<Edge> edges;
  for (size_t r = 0; r < lo.size(); ++r) {
    zs.push_back(lo[r].y());
    zs.push_back(hi[r].y());
    edges.push_back({lo[r].x(), 1, r});
    edges.push_back({hi[r].x(), -1, r});
  }
  std::sort(zs.begin(), zs.end());
  zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.y < b.y; });
  CoverTree tree(zs);
  for (size_t e = 0; e < edges.size(); ++e) {
    if (e > 0) {
      const double y0 = edges[e - 1].y, y1 = edges[e].y;
      out.area += tree.length() * (y1 - y0);
      out.first_y += tree.length() * 0.5 * (y1 * y1 - y0 * y0);
      out.first_z += tree.moment() * (y1 - y0);
    }
    tree.change(lo[edges[e].rect].y(), hi[edges[e].rect].y(), edges[e].delta);
  }
  return out;
}

// Exact union of boxes that are axis-aligned in the frame `frame`: slabs between the boxes'
// x faces, each the union of the rectangles of the boxes that span it, swept along y with the
// covered z intervals in a segment tree. O(k^2 log k) for k boxes.
VolumeMoment alignedUnion(const std::vector<const Box*>& boxes, const Pose& frame) {
  const Eigen::Matrix3d to_frame = frame.orientation.conjugate().toRotationMatrix();
  std::vector<Vec3> lo, hi;
  std::vector<double> xs;
  for (const Box* box : boxes) {
    const Vec3 centre = to_frame * (box->origin.position - frame.position);
    const Vec3 half =
        (to_frame * box->origin.orientation.toRotationMatrix()).cwiseAbs() * (0.5 * box->size);
    lo.push_back(centre - half);
    hi.push_back(centre + half);
    xs.push_back(lo.back().x());
    xs.push_back(hi.back().x());
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  std::vector<Eigen::Vector2d> rect_lo, rect_hi;
  for (size_t s = 0; s + 1 < xs.size(); ++s) {
    const double x0 = xs[s], x1 = xs[s + 1], dx = x1 - x0;
    rect_lo.clear();
    rect_hi.clear();
    for (size_t n = 0; n < boxes.size(); ++n) {
      if (lo[n].x() <= x0 && hi[n].x() >= x1) {
        rect_lo.emplace_back(lo[n].y(), lo[n].z());
        rect_hi.emplace_back(hi[n].y(), hi[n].z());
      }
    }
    const AreaMoments a = rectangleUnion(rect_lo, rect_hi);
    volume += a.area * dx;
    moment += dx * Vec3(0.5 * (x0 + x1) * a.area, a.first_y, a.first_z);
  }
  // The moment about the body origin: the frame's origin carries the volume.
  return {volume, frame.orientation * moment + volume * frame.position};
}

// An earlier box as the lines through a box see it: the first line's middle, the steps between
// lines and the lines' direction in its frame (with their inverses: 0 where parallel), its half
// size, and the indices of the lines that can meet it.
struct LineFrame {
  Vec3 first, step_b, step_c, along, half;
  int b0 = 0, b1 = -1, c0 = 0, c1 = -1;
  Vec3 inverse_along = Vec3::Zero();
  bool parallel[3] = {false, false, false};
};

// `other` for the n x n lines parallel to the x edge of `box`, whose middles are
// first + b step_b + c step_c (body frame).
LineFrame lineFrame(const Box& box, const Box& other, int n, const Vec3& first, const Vec3& step_b,
                    const Vec3& step_c) {
  const Quat to_other = other.origin.orientation.conjugate();
  LineFrame f;
  f.first = inBox(other, first);
  f.step_b = to_other * step_b;
  f.step_c = to_other * step_c;
  f.along = to_other * (box.origin.orientation * Vec3::UnitX());
  f.half = 0.5 * other.size;
  for (int k = 0; k < 3; ++k) {
    f.parallel[k] = std::abs(f.along[k]) < 1e-15;
    if (!f.parallel[k]) f.inverse_along[k] = 1.0 / f.along[k];
  }
  // The lines that can meet it: those within its corners' span across the box's face.
  Eigen::AlignedBox3d seen;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 half(corner & 1 ? 0.5 : -0.5, corner & 2 ? 0.5 : -0.5, corner & 4 ? 0.5 : -0.5);
    seen.extend(inBox(box, other.origin.apply(half.cwiseProduct(other.size))));
  }
  auto line = [n](double at, double edge) {
    return static_cast<int>(std::floor((at / edge + 0.5) * n - 0.5));
  };
  f.b0 = line(seen.min().y(), box.size.y());
  f.b1 = line(seen.max().y(), box.size.y()) + 1;
  f.c0 = line(seen.min().z(), box.size.z());
  f.c1 = line(seen.max().z(), box.size.z()) + 1;
  return f;
}

// The length and first moment (in t) of what `others` cover of line (b, c), t in
// [-dx/2, dx/2]; `covered` is scratch.
std::pair<double, double> coveredOnLine(const std::vector<LineFrame>& others, int b, int c,
                                        double dx,
                                        std::vector<std::pair<double, double>>& covered) {
  covered.clear();
  for (const LineFrame& other : others) {
    if (b < other.b0 || b > other.b1 || c < other.c0 || c > other.c1) continue;
    double t0 = -0.5 * dx, t1 = 0.5 * dx;
    const Vec3 o = other.first + b * other.step_b + c * other.step_c;
    for (int k = 0; k < 3 && t0 < t1; ++k) {
      const double half = other.half[k];
      if (other.parallel[k]) {
        if (std::abs(o[k]) > half) t1 = t0;
        continue;
      }
      const double ta = (-half - o[k]) * other.inverse_along[k],
                   tb = (half - o[k]) * other.inverse_along[k];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    if (t0 < t1) covered.emplace_back(t0, t1);
  }
  std::sort(covered.begin(), covered.end());
  double length = 0.0, first_moment = 0.0, end = -0.5 * dx;
  for (const auto& [t0, t1] : covered) {
    const double from = std::max(t0, end);
    if (t1 <= from) continue;
    length += t1 - from;
    first_moment += 0.5 * (t1 * t1 - from * from);
    end = t1;
  }
  return {length, first_moment};
}

// Each box of `group` adds the part of it that none of the boxes `earlier_of` it holds: all of
// it, less what they cover of n x n lines parallel to its x edge over its y-z face, measured
// exactly along each line, by the midpoint rule across them.
VolumeMoment linesUnion(const std::vector<Box>& boxes, const std::vector<size_t>& group,
                        const std::vector<std::vector<size_t>>& earlier_of, int n) {
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  std::vector<std::pair<double, double>> covered;
  std::vector<LineFrame> others;
  for (const size_t i : group) {
    const Box& box = boxes[i];
    volume += box.size.prod();
    moment += box.size.prod() * box.origin.position;
    if (earlier_of[i].empty()) continue;
    const double dx = box.size.x(), area = box.size.y() * box.size.z() / (n * n);
    const Vec3 along = box.origin.orientation * Vec3::UnitX();
    auto lineMiddle = [&](int b, int c) {
      return box.origin.apply(
          Vec3(0.0, box.size.y() * ((b + 0.5) / n - 0.5), box.size.z() * ((c + 0.5) / n - 0.5)));
    };
    const Vec3 first = lineMiddle(0, 0), step_b = lineMiddle(1, 0) - first,
               step_c = lineMiddle(0, 1) - first;
    others.clear();
    int b_lo = n, b_hi = -1, c_lo = n, c_hi = -1;
    for (const size_t j : earlier_of[i]) {
      others.push_back(lineFrame(box, boxes[j], n, first, step_b, step_c));
      b_lo = std::min(b_lo, others.back().b0);
      b_hi = std::max(b_hi, others.back().b1);
      c_lo = std::min(c_lo, others.back().c0);
      c_hi = std::max(c_hi, others.back().c1);
    }
    for (int b = std::max(0, b_lo); b <= std::min(n - 1, b_hi); ++b) {
      for (int c = std::max(0, c_lo); c <= std::min(n - 1, c_hi); ++c) {
        const auto [length, first_moment] = coveredOnLine(others, b, c, dx, covered);
        volume -= area * length;
        moment -= area * (length * (first + b * step_b + c * step_c) + first_moment * along);
      }
    }
  }
  return {volume, moment};
}

size_t findRoot(std::vector<size_t>& parent, size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<std::pair<size_t, size_t>> overlappingBounds(
    const std::vector<Eigen::AlignedBox3d>& bounds, double margin) {
  std::vector<size_t> order(bounds.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return bounds[a].min().x() < bounds[b].min().x() ||
           (bounds[a].min().x() == bounds[b].min().x() && a < b);
  });
  std::vector<std::pair<size_t, size_t>> pairs;
  for (size_t p = 0; p < order.size(); ++p) {
    const Eigen::AlignedBox3d& a = bounds[order[p]];
    for (size_t q = p + 1; q < order.size(); ++q) {
      const Eigen::AlignedBox3d& b = bounds[order[q]];
      if (b.min().x() >= a.max().x() - margin) break;
      if ((b.min().array() < a.max().array() - margin).all() &&
          (a.min().array() < b.max().array() - margin).all()) {
        pairs.emplace_back(std::min(order[p], order[q]), std::max(order[p], order[q]));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

namespace {

// The boxes grouped by their bounds sharing volume (group members in increasing order, groups
// under their root box), whether each group is axis-aligned with its first box, and the pairs.
struct BoxGroups {
  std::vector<std::pair<size_t, size_t>> pairs;
  std::vector<std::vector<size_t>> groups;  // indexed by root; empty for non-roots
  std::vector<bool> aligned;                // by the group's first box
  size_t turned_pairs = 0;                  // pairs within groups that are not aligned
};

BoxGroups groupBoxes(const std::vector<Box>& boxes) {
  BoxGroups g;
  std::vector<Eigen::AlignedBox3d> box_bounds;
  double largest = 0.0;
  for (const Box& box : boxes) {
    box_bounds.push_back(boxBounds(box));
    largest = std::max(largest, box.size.maxCoeff());
  }
  g.pairs = overlappingBounds(box_bounds, 1e-12 * largest);
  std::vector<size_t> parent(boxes.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [a, b] : g.pairs) parent[findRoot(parent, a)] = findRoot(parent, b);
  g.groups.resize(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) g.groups[findRoot(parent, i)].push_back(i);
  g.aligned.assign(boxes.size(), true);
  for (const auto& group : g.groups) {
    if (group.size() < 2) continue;
    const Eigen::Matrix3d first = boxes[group[0]].origin.orientation.conjugate().toRotationMatrix();
    for (const size_t i : group) {
      if (!isSignedPermutation(first * boxes[i].origin.orientation.toRotationMatrix())) {
        g.aligned[group[0]] = false;
      }
    }
  }
  for (const auto& [a, b] : g.pairs) {
    if (!g.aligned[g.groups[findRoot(parent, a)][0]]) ++g.turned_pairs;
  }
  return g;
}

}  // namespace

Eigen::AlignedBox3d boxBounds(const Box& box) {
  const Vec3 half = box.origin.orientation.toRotationMatrix().cwiseAbs() * (0.5 * box.size);
  return Eigen::AlignedBox3d(box.origin.position - half, box.origin.position + half);
}

size_t turnedOverlaps(const std::vector<Box>& boxes) { return groupBoxes(boxes).turned_pairs; }

BoxUnion unionOfBoxes(const std::vector<Box>& boxes) {
  BoxUnion u;
  if (boxes.empty()) return u;
  const BoxGroups g = groupBoxes(boxes);
  std::vector<std::vector<size_t>> earlier_of(boxes.size());
  for (const auto& [a, b] : g.pairs) earlier_of[b].push_back(a);
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const auto& group : g.groups) {
    if (group.empty()) continue;
    VolumeMoment part;
    if (group.size() == 1) {
      const Box& box = boxes[group[0]];
      part = {box.size.prod(), box.size.prod() * box.origin.position};
    } else if (g.aligned[group[0]]) {
      std::vector<const Box*> members;
      for (const size_t i : group) members.push_back(&boxes[i]);
      part = alignedUnion(members, boxes[group[0]].origin);
    } else {
      part = linesUnion(boxes, group, earlier_of, kUnionLines);
    }
    volume += part.volume;
    moment += part.moment;
  }
  u.volume = volume;
  if (volume > 0.0) u.centroid = moment / volume;
  return u;
}

}  // namespace flapsim
