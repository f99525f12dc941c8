#include "fluid/box_union.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <utility>

namespace flapsim {

namespace {

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

}  // namespace flapsim
