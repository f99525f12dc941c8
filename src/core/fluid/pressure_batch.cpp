#include "fluid/pressure_batch.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "fluid/body_flow.h"
#include "fluid/pressure_kernel.h"

namespace flapsim {

// fluid/pressure_batch_avx2.cpp: the faces of a table, the 4 x 4 grids [0, squares) and the
// 1 x 4 ones [squares, stride).
void pressureTableAvx2(double* table, int stride, int squares, const Flows& flows, bool wind);

namespace {

constexpr int kWidest = 4;  // lanes of the widest kernel: each shape is padded to a multiple

int padded(int faces) { return (faces + kWidest - 1) / kWidest * kWidest; }

// Whether a face is a 4 x 4 grid (0), a 1 x 4 one either way round (1), or neither (-1: no
// kernel takes it).
int shapeOf(const SurfaceFace& f) {
  if (f.nu <= 0 || f.nv <= 0 || f.cell_count != f.nu * f.nv) return -1;
  if (std::max(f.nu, f.nv) != 4) return -1;
  const int rows = std::min(f.nu, f.nv);
  return rows == 4 ? 0 : rows == 1 ? 1 : -1;
}

bool takes(const AeroSurface& s) {
  if (s.faces.empty()) return false;
  return std::all_of(s.faces.begin(), s.faces.end(),
                     [](const SurfaceFace& f) { return shapeOf(f) >= 0; });
}

}  // namespace

namespace {

std::atomic<bool>& simdAllowed() {
  static std::atomic<bool> allowed{[] {
    const char* env = std::getenv("FLAPSIM_SIMD");
    return !(env && std::strcmp(env, "off") == 0);
  }()};
  return allowed;
}

}  // namespace

bool PressureBatch::avx2() {
  static const bool cpu = __builtin_cpu_supports("avx2") != 0;
  return cpu && simdAllowed().load(std::memory_order_relaxed);
}

void PressureBatch::allowSimd(bool on) { simdAllowed().store(on, std::memory_order_relaxed); }

void PressureBatch::build(const std::vector<const AeroSurface*>& surfaces) {
  const size_t n = surfaces.size();
  faces_.clear();
  first_face_.assign(n + 1, 0);
  held_.assign(n, 0);
  drag_.assign(n, 0.0);
  flows_.assign(kFlowColumns * (n + 1), 0.0);
  rotations_.assign(n, Eigen::Matrix3d::Identity());
  int count[2] = {0, 0};
  for (size_t b = 0; b < n; ++b) {
    held_[b] = takes(*surfaces[b]);
    drag_[b] = surfaces[b]->drag_coefficient;
    if (!held_[b]) continue;
    for (const SurfaceFace& f : surfaces[b]->faces) ++count[shapeOf(f)];
  }
  squares_ = padded(count[0]);
  stride_ = squares_ + padded(count[1]);
  table_.assign(static_cast<size_t>(kPressureColumns) * stride_, 0.0);
  body_.assign(stride_, static_cast<int>(n));
  int next[2] = {0, squares_};
  for (size_t b = 0; b < n; ++b) {
    first_face_[b] = static_cast<int>(faces_.size());
    if (!held_[b]) continue;
    for (const SurfaceFace& f : surfaces[b]->faces) {
      addFace(static_cast<int>(b), *surfaces[b], f, next[shapeOf(f)]++);
    }
  }
  first_face_[n] = static_cast<int>(faces_.size());
}

void PressureBatch::addFace(int body, const AeroSurface& s, const SurfaceFace& f, int j) {
  body_[j] = body;
  auto set = [this, j](int column, double value) {
    table_[static_cast<size_t>(column) * stride_ + j] = value;
  };
  auto setVec = [&set](int column, const Vec3& v) {
    for (int i = 0; i < 3; ++i) set(column + i, v[i]);
  };
  const SurfaceCell& first = s.cells[f.first_cell];
  setVec(kNormal, f.normal);
  setVec(kCentreCrossNormal, f.centre_x_normal);
  setVec(kStepUCrossNormal, f.step_u_x_normal);
  setVec(kStepVCrossNormal, f.step_v_x_normal);
  setVec(kFirstCentre, first.centre);
  setVec(kStepU, f.step_u);
  setVec(kStepV, f.step_v);
  set(kArea, first.area);
  set(kULess1, f.nu - 1);
  set(kVLess1, f.nv - 1);
  set(kSwap, f.nv >= f.nu ? 1.0 : -1.0);  // pressureLaw's sums run along the longer edge
  faces_.push_back(j);
}

bool PressureBatch::gatherFlows(const std::vector<BodyKinematics>& kin, const AirParams& air) {
  const size_t stride = held_.size() + 1;
  bool wind = false;
  for (size_t b = 0; b < held_.size(); ++b) {
    if (!held_[b]) continue;
    const BodyFlow flow(kin[b], air);  // as pressureLaw's
    rotations_[b] = flow.rot;
    for (int i = 0; i < 3; ++i) {
      flows_[(kVelocity + i) * stride + b] = flow.v[i];
      flows_[(kOmega + i) * stride + b] = flow.w[i];
      flows_[(kWind + i) * stride + b] = flow.wind[i];
    }
    flows_[kHalfRhoCd * stride + b] = 0.5 * air.density * drag_[b];
    wind = wind || !flow.wind.isZero(0.0);
  }
  return wind;
}

void PressureBatch::run(const std::vector<BodyKinematics>& kin, const AirParams& air,
                        std::vector<Wrench>& out, Kernel kernel) {
  if (kernel == Kernel::kAvx2 && !__builtin_cpu_supports("avx2")) {
    throw std::logic_error("PressureBatch: the AVX2 kernel asked for on a CPU without AVX2");
  }
  const bool simd = kernel == Kernel::kAvx2 || (kernel == Kernel::kAuto && avx2());
  out.resize(kin.size());
  const bool wind = gatherFlows(kin, air);
  const Flows flows{flows_.data(), static_cast<int>(held_.size() + 1), body_.data()};
  double* t = table_.data();
  if (simd) {
    pressureTableAvx2(t, stride_, squares_, flows, wind);
  } else {
    pressureTable<ScalarLane, GridShape::k4x4>(t, stride_, 0, squares_, flows, wind);
    pressureTable<ScalarLane, GridShape::k1x4>(t, stride_, squares_, stride_, flows, wind);
  }
  // Each body's wrench, its faces in pressureLaw's order (those that do not advance add +0).
  const size_t s = static_cast<size_t>(stride_);
  const double *fx = t + kForce * s, *fy = fx + s, *fz = fy + s;
  const double *tx = t + kTorque * s, *ty = tx + s, *tz = ty + s;
  for (size_t b = 0; b < held_.size(); ++b) {
    if (!held_[b]) continue;
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    for (int f = first_face_[b]; f < first_face_[b + 1]; ++f) {
      const int j = faces_[f];
      force -= Vec3(fx[j], fy[j], fz[j]);
      torque -= Vec3(tx[j], ty[j], tz[j]);
    }
    out[b] = Wrench{rotations_[b] * force, rotations_[b] * torque};
  }
}

}  // namespace flapsim
