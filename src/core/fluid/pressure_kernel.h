// The pressure law's per-face arithmetic (fluid/pressure.cpp: pressureLaw) over many faces at
// once, written once for a lane type: `double` (one face at a time, the scalar path) or a
// SIMD register of four faces (fluid/pressure_batch_avx2.cpp). Every lane performs the same
// IEEE operations in the same order as pressureLaw does for its face (the 4 x 4 grid's sums
// in gridSums4x4's order, the 1 x 4 grid's in gridSums<1, 4>'s), so all paths give the same
// bits. Included by the kernel's translation units only: internal to each (an unnamed
// namespace), free of library code, so that a unit compiled for AVX2 shares no function with
// the rest of the library. Private to flapsim_core.
#pragma once

namespace flapsim {

// The columns of a face table (PressureBatch): per face, the constants of its grid (body
// frame) and the kernel's results. Column c of face j is data[c * stride + j].
enum PressureColumn {
  kNormal = 0,             // 3 columns each: x, y, z
  kCentreCrossNormal = 3,  // SurfaceFace::centre_x_normal
  kStepUCrossNormal = 6,
  kStepVCrossNormal = 9,
  kFirstCentre = 12,  // the first cell's centre
  kStepU = 15,
  kStepV = 18,
  kArea = 21,    // of one cell
  kULess1 = 22,  // nu - 1
  kVLess1 = 23,  // nv - 1
  kSwap = 24,    // -1: the grid's longer edge is u (sums taken with u and v swapped), else 1
  kForce = 25,   // results: p n and the torque subtracted from the body's (zeros where the
  kTorque = 28,  // face does not advance into the air)
  kPressureColumns = 31
};

// The columns of the bodies' flows (BodyFlow, body frame), gathered by each face's body.
enum FlowColumn { kVelocity = 0, kOmega = 3, kWind = 6, kHalfRhoCd = 9, kFlowColumns = 10 };

// The bodies' flows: column c of body b is data[c * stride + b]; body[j] is face j's body.
struct Flows {
  const double* data;
  int stride;
  const int* body;
};

namespace {

// A face's cells as one grid shape: 4 x 4 (a box's face), or 1 x 4 (a plate's rim).
enum class GridShape { k4x4, k1x4 };

template <class L>
struct Vec3Of {
  L x, y, z;
};

template <class L>
inline Vec3Of<L> loadVec(const double* data, int stride, int column, int j) {
  return {L::load(data + column * stride + j), L::load(data + (column + 1) * stride + j),
          L::load(data + (column + 2) * stride + j)};
}
template <class L>
inline void storeVec(double* data, int stride, int column, int j, const Vec3Of<L>& v) {
  L::store(data + column * stride + j, v.x);
  L::store(data + (column + 1) * stride + j, v.y);
  L::store(data + (column + 2) * stride + j, v.z);
}
// Eigen's orders for fixed-size 3-vectors: (x + y) + z.
template <class L>
inline L dot(const Vec3Of<L>& a, const Vec3Of<L>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class L>
inline Vec3Of<L> cross(const Vec3Of<L>& a, const Vec3Of<L>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The sums over a grid's cells (see pressure.cpp: GridAxes, GridSums).
template <class L>
struct LaneSums {
  L sum, across, along;
};

// gridSums4x4: rows a0, a0 + 1 in the two halves of a pair, columns one by one.
template <class L>
inline LaneSums<L> sums4x4(L n0, L na, L nb, L q00, L q0a, L q0b, L qaa, L qab, L qbb) {
  const L zero = L::splat(0.0);
  L sum[2] = {zero, zero}, across[2] = {zero, zero}, along[2] = {zero, zero};
  for (int a0 = 0; a0 < 4; a0 += 2) {
    for (int h = 0; h < 2; ++h) {
      const L a = L::splat(h + static_cast<double>(a0));
      const L un_a = n0 + a * na;
      const L q_a = q00 + a * (q0a + a * qaa), q_ab = q0b + a * qab;
      L row = zero, row_b = zero;
      for (int j = 0; j < 4; ++j) {
        const L b = L::splat(j);
        const L un = L::max0(un_a + b * nb);
        const L p = L::sqrt(L::max0(q_a + b * (q_ab + b * qbb))) * un;
        row = row + p;
        row_b = row_b + p * b;
      }
      sum[h] = sum[h] + row;
      across[h] = across[h] + a * row;
      along[h] = along[h] + row_b;
    }
  }
  return {sum[0] + sum[1], across[0] + across[1], along[0] + along[1]};
}

// gridSums<1, 4>: one row, columns b0, b0 + 1 in the two halves of a pair.
template <class L>
inline LaneSums<L> sums1x4(L n0, L na, L nb, L q00, L q0a, L q0b, L qaa, L qab, L qbb) {
  const L zero = L::splat(0.0), a = zero;
  const L un_a = n0 + a * na;
  const L q_a = q00 + a * (q0a + a * qaa), q_ab = q0b + a * qab;
  L row[2] = {zero, zero}, row_b[2] = {zero, zero};
  for (int b0 = 0; b0 < 4; b0 += 2) {
    for (int h = 0; h < 2; ++h) {
      const L b = L::splat(h + static_cast<double>(b0));
      const L un = L::max0(un_a + b * nb);
      const L p = L::sqrt(L::max0(q_a + b * (q_ab + b * qbb))) * un;
      row[h] = row[h] + p;
      row_b[h] = row_b[h] + p * b;
    }
  }
  LaneSums<L> s[2];
  for (int h = 0; h < 2; ++h) s[h] = {zero + row[h], zero + a * row[h], zero + row_b[h]};
  return {s[0].sum + s[1].sum, s[0].across + s[1].across, s[0].along + s[1].along};
}

template <class L>
inline Vec3Of<L> gatherVec(const Flows& f, int column, int j) {
  const int* b = f.body + j;
  return {L::gather(f.data + column * f.stride, b), L::gather(f.data + (column + 1) * f.stride, b),
          L::gather(f.data + (column + 2) * f.stride, b)};
}

// pressureLaw's loop body for the faces [j, j + L::kWidth) of a table of one grid shape.
// kWindy: the bodies feel a wind (without, subtracting its zero would change no bit).
template <class L, GridShape kShape, bool kWindy>
inline void pressureFaces(double* t, int stride, int j, const Flows& flows) {
  const L two = L::splat(2.0);
  const Vec3Of<L> w = gatherVec<L>(flows, kOmega, j);
  Vec3Of<L> v = gatherVec<L>(flows, kVelocity, j), wind{};
  if (kWindy) wind = gatherVec<L>(flows, kWind, j);
  const Vec3Of<L> n = loadVec<L>(t, stride, kNormal, j);
  const Vec3Of<L> cxn = loadVec<L>(t, stride, kCentreCrossNormal, j);
  const Vec3Of<L> uxn = loadVec<L>(t, stride, kStepUCrossNormal, j);
  const Vec3Of<L> vxn = loadVec<L>(t, stride, kStepVCrossNormal, j);
  const Vec3Of<L> drift = kWindy ? Vec3Of<L>{v.x - wind.x, v.y - wind.y, v.z - wind.z} : v;
  const L n0 = dot(drift, n) + dot(w, cxn);
  const L n_i = dot(w, uxn), n_j = dot(w, vxn);
  // The face is skipped (no force) where its largest u.n over the cell centres is <= 0.
  const L top = n0 + L::maxPositive(L::load(t + kULess1 * stride + j) * n_i) +
                L::maxPositive(L::load(t + kVLess1 * stride + j) * n_j);
  const L advances = L::notAtMostZero(top);
  const Vec3Of<L> r = cross(w, loadVec<L>(t, stride, kFirstCentre, j));
  Vec3Of<L> u0{v.x + r.x, v.y + r.y, v.z + r.z};
  if (kWindy) u0 = {u0.x - wind.x, u0.y - wind.y, u0.z - wind.z};
  const Vec3Of<L> du = cross(w, loadVec<L>(t, stride, kStepU, j));
  const Vec3Of<L> dv = cross(w, loadVec<L>(t, stride, kStepV, j));
  const L qii = dot(du, du), qij = two * dot(du, dv), qjj = dot(dv, dv);
  const L k = L::gather(flows.data + kHalfRhoCd * flows.stride, flows.body + j) *
              L::load(t + kArea * stride + j);
  const L q00 = dot(u0, u0), q0i = two * dot(u0, du), q0j = two * dot(u0, dv);
  // Sums along the grid's longer edge: with u and v swapped where u is the longer.
  const L swap = L::load(t + kSwap * stride + j);
  const L na = L::select(swap, n_i, n_j), nb = L::select(swap, n_j, n_i);
  const L q0a = L::select(swap, q0i, q0j), q0b = L::select(swap, q0j, q0i);
  const L qaa = L::select(swap, qii, qjj), qbb = L::select(swap, qjj, qii);
  const LaneSums<L> g = kShape == GridShape::k4x4
                            ? sums4x4(n0, na, nb, q00, q0a, q0b, qaa, qij, qbb)
                            : sums1x4(n0, na, nb, q00, q0a, q0b, qaa, qij, qbb);
  const L across = L::select(swap, g.across, g.along), along = L::select(swap, g.along, g.across);
  const L p = k * g.sum, ka = k * across, kb = k * along;
  // Where the face does not advance, +0: the body's sums (never -0) stay as they are.
  auto keep = [advances](L x) { return L::onlyIf(advances, x); };
  storeVec<L>(t, stride, kForce, j, {keep(p * n.x), keep(p * n.y), keep(p * n.z)});
  storeVec<L>(t, stride, kTorque, j,
              {keep(p * cxn.x + ka * uxn.x + kb * vxn.x), keep(p * cxn.y + ka * uxn.y + kb * vxn.y),
               keep(p * cxn.z + ka * uxn.z + kb * vxn.z)});
}

// One face at a time: the scalar path, for any x86-64 (and the reference of the SIMD one).
struct ScalarLane {
  static constexpr int kWidth = 1;
  double v;
  static ScalarLane splat(double x) { return {x}; }
  static ScalarLane load(const double* p) { return {*p}; }
  static void store(double* p, ScalarLane x) { *p = x.v; }
  // Eigen's max(x, 0) on a packet: 0 > x ? 0 : x (x itself for -0 and NaN).
  static ScalarLane max0(ScalarLane x) { return {0.0 > x.v ? 0.0 : x.v}; }
  // std::max(0.0, x): x > 0 ? x : 0.
  static ScalarLane maxPositive(ScalarLane x) { return {x.v > 0.0 ? x.v : 0.0}; }
  static ScalarLane sqrt(ScalarLane x) { return {__builtin_sqrt(x.v)}; }
  // `a`, or `b` where `swap` < 0.
  static ScalarLane select(ScalarLane swap, ScalarLane a, ScalarLane b) {
    return swap.v < 0.0 ? b : a;
  }
  // Whether x is not <= 0 (NaN too): a mask for onlyIf.
  static ScalarLane notAtMostZero(ScalarLane x) { return {x.v <= 0.0 ? 0.0 : 1.0}; }
  // x where `mask` is set, else +0.
  static ScalarLane onlyIf(ScalarLane mask, ScalarLane x) { return {mask.v != 0.0 ? x.v : 0.0}; }
  static ScalarLane gather(const double* column, const int* body) { return {column[*body]}; }
};
inline ScalarLane operator+(ScalarLane a, ScalarLane b) { return {a.v + b.v}; }
inline ScalarLane operator-(ScalarLane a, ScalarLane b) { return {a.v - b.v}; }
inline ScalarLane operator*(ScalarLane a, ScalarLane b) { return {a.v * b.v}; }

// The faces [begin, end) of a table (a multiple of L::kWidth apart), all of one grid shape.
template <class L, GridShape kShape>
inline void pressureTable(double* t, int stride, int begin, int end, const Flows& flows,
                          bool wind) {
  for (int j = begin; j < end; j += L::kWidth) {
    if (wind) {
      pressureFaces<L, kShape, true>(t, stride, j, flows);
    } else {
      pressureFaces<L, kShape, false>(t, stride, j, flows);
    }
  }
}

}  // namespace
}  // namespace flapsim
