// The paper's pressure law (fluid/pressure.h: pressureLaw) on every grid face of a creature's
// aero bodies at once: the faces' constants in one table (structure of arrays, the 4 x 4
// grids first, then the 1 x 4 ones), the per-face arithmetic (fluid/pressure_kernel.h) four
// faces at a time with AVX2 where the CPU has it, else one face at a time, each face reading
// its body's flow, then each body's wrench summed face by face in its own order. Either path
// gives pressureLaw's bits, body by body. Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/air_model.h"

namespace flapsim {

class PressureBatch {
 public:
  enum class Kernel { kAuto, kScalar, kAvx2 };

  // Whether kAuto runs the AVX2 kernel: if the CPU has AVX2, unless the environment
  // variable FLAPSIM_SIMD is "off" at start-up or allowSimd(false) was called (both force the
  // scalar path in every world: the same results, for comparison and tests).
  static bool avx2();
  static void allowSimd(bool on);

  // The bodies with these surfaces (index = body): it holds those whose every face is a
  // regular grid of 4 x 4 or 1 x 4 cells (either way round), as box faces and plate rims
  // are at the default subdivisions; the others are left to pressureLaw.
  void build(const std::vector<const AeroSurface*>& surfaces);
  bool holds(size_t body) const { return body < held_.size() && held_[body]; }

  // pressureLaw(FluidInput{kin[b], surface b, air}, nullptr) into out[b] for every body b it
  // holds (kin: one per body, `out` resized to that), with the kernel asked for (kAuto: AVX2
  // if avx2(); kAvx2 where the CPU lacks it: std::logic_error).
  void run(const std::vector<BodyKinematics>& kin, const AirParams& air, std::vector<Wrench>& out,
           Kernel kernel = Kernel::kAuto);

 private:
  void addFace(int body, const AeroSurface& s, const SurfaceFace& f, int j);
  // The flows of the held bodies; returns whether any feels a wind.
  bool gatherFlows(const std::vector<BodyKinematics>& kin, const AirParams& air);

  // PressureColumn columns of `stride_` faces: the 4 x 4 grids in [0, squares_), the 1 x 4
  // ones after, each shape padded to a multiple of four faces (zeros, of the body `bodies`).
  std::vector<double> table_;
  int stride_ = 0, squares_ = 0;
  std::vector<int> body_;        // per table entry
  std::vector<int> faces_;       // table entries of the held bodies, body by body, in face order
  std::vector<int> first_face_;  // per body: its first entry of faces_ (size bodies + 1)
  std::vector<char> held_;       // per body
  std::vector<double> drag_;     // per body: its surface's drag coefficient
  // Per body (and a last one, zeros, for the padding): FlowColumn columns; its rotation.
  std::vector<double> flows_;
  std::vector<Eigen::Matrix3d> rotations_;
};

}  // namespace flapsim
