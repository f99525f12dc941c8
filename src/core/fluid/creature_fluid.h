// The fluid of one creature: its aero bodies (the links that the air acts on), each with its
// surface, its added mass and what the fluid stage (world/fluid_stage.h) found in the last
// (sub)step: the explicit wrench and the implicit part (added mass, linearised drag) that the
// servo stage solves inside Bullet's step. Private to flapsim_core.
#pragma once

#include <string>
#include <vector>

#include "dynamics/spatial.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/world.h"
#include "fluid/pressure_batch.h"

namespace flapsim {

// A link that the air acts on (aero enabled, with boxes); other links have none.
struct AeroBody {
  int link = 0;           // model link index (0 = root = Bullet base)
  std::string model;      // the link's own air model, empty for the world's
  AirModelPtr own_model;  // that model (null for the world's), resolved at spawn
  AeroSurface surface;
  // The fluid's implicit part (fluid/added_mass.h), spatial, about the COM: the added mass
  // of the link's plates at density 1 in body axes, and its factor; this step's added mass
  // (factored) and step x linearised drag, in world axes.
  Mat6 added_mass = Mat6::Zero();
  SpatialFactor added_factor;
  bool has_added_mass = false;  // added_mass is not zero
  SpatialFactor added;          // empty unless has_added_mass
  // What `added` was turned with (CreatureFluid::addedMass): the link's rotation and the
  // density; not valid after a new surface.
  Mat3 added_rotation = Mat3::Zero();
  double added_density = 0.0;
  bool added_valid = false;
  Mat6 drag = Mat6::Zero();
  bool drag_zero = true;  // drag is zero (kept so without rewriting it each step)
  double mass = 0.0;      // the link's own (a lower bound of its effective mass in the tree)
  double area = 0.0;      // of all its air-facing cells
  Mat3 normal_area = Mat3::Zero();  // sum of area n n^T over its cells, body axes
  // dragMass's last answer and what it was asked for (density; forces along normals).
  double drag_mass = 0.0, drag_mass_density = -1.0;
  bool drag_mass_normals = false;
  LinkAero last;  // the wrench of the last step
  // The velocity products its plates shed into the wake at the start of the last step
  // (AddedMassProducts::kShed), about last.com: a part of last.wrench.
  Wrench shed;
};

// A drag rate (kg/s) above this many link masses per step is treated implicitly.
constexpr double kImplicitDragRatio = 2.0;

// The mass m that resists the drag of aero body `a` in needsImplicitDrag. The link's own,
// unless its law's forces lie along its cells' normals (`along_normals`,
// AirModel::forcesAlongNormals) and its plates carry added mass at this density: then the
// cells' area over sum_c area_c n_c^T (m_own 1 + density A_t)^-1 n_c (A_t: the added mass's
// translational block), each cell's share resisted by the link's mass plus the fluid it
// carries along that cell's normal, which the velocity update holds implicitly (a wing of the
// flap unit: 4 g of its own, 16 g of air). Exactly the link's own mass without added mass.
double dragMass(AeroBody& a, double density, bool along_normals);

// Whether the drag on aero body `a` is stiff enough for the implicit treatment: if step x
// rho C A |u|max / m (C: its law's force coefficient, AirModel::forceCoefficient; A: all its
// cells, |u|max: its fastest point relative to the air, reach: from its COM to its farthest
// corner; m: `mass`, dragMass's) exceeds kImplicitDragRatio. With at most
// about half of a body's cells advancing, that bounds step x (d|F|/du) / m by 1, half of
// the 2 at which the explicit step reverses a face-on cell's normal speed. Below it the
// drag is explicit, first order, cheaper, and more accurate than its linearisation across
// a stroke's turn: on the flap unit, always linearised, the height after 3 s is off the
// 1/16 ms reference's by 2 % per ms of step; explicit, by at most 0.4 % up to 6 ms.
bool needsImplicitDrag(const AeroBody& a, const BodyKinematics& kin, const AirParams& air,
                       double coefficient, double mass, double reach, double step);

// The added mass of a link's plate-like boxes at density 1 (AeroBody::added_mass).
Mat6 linkAddedMass(const LinkModel& l, const AirParams& air);

// The aero bodies of one creature, in link order, with what the fluid stage found in the
// last (sub)step; written by AirStage and by addedMass() only.
class CreatureFluid {
 public:
  CreatureFluid(const CreatureModel& m, const AirParams& air);
  // Rebuilds the surfaces for new air parameters, keeping the rest: all of them when the
  // subdivisions or added mass changed, else only the drag coefficients (O(cells)).
  void resurface(const CreatureModel& m, const AirParams& air, bool geometry_changed = true);

  const std::vector<AeroBody>& bodies() const { return bodies_; }
  // Per aero body, its kinematics at the start of the last (sub)step's fluid stage.
  const std::vector<BodyKinematics>& kinematics() const { return kinematics_; }
  // Whether this (sub)step's aero bodies carry implicit fluid matrices (added mass or drag).
  bool active() const { return active_; }
  // The added mass of aero body i at `density` in world axes (`rotation`: its link's, to
  // world), about its COM, factored (empty without added mass); turned again only if the
  // rotation or the density changed since it last was (the end of a step's momentum has the
  // next step's rotations).
  const SpatialFactor& addedMass(size_t i, const Mat3& rotation, double density);
  // Whether some plate of it carries fluid along (an aero body with added mass).
  bool carries() const {
    for (const AeroBody& a : bodies_) {
      if (a.has_added_mass) return true;
    }
    return false;
  }
  // The fluid's acceleration over a (sub)step of `step` whose fluid velocity is `velocity`
  // (world frame): its change since the last (sub)step over `step` (zero for the first one, or
  // after forgetFlow()), and remembers it.
  Vec3 flowAcceleration(const Vec3& velocity, double step);
  // After a state set from outside a step: no change of the fluid's velocity is pending.
  void forgetFlow() { flow_known_ = false; }
  // The products aero body i shed at the end of the step (`end`, about its COM there,
  // `end_com`): its wrench of the step then holds the mean of those of the start and the end,
  // the impulse the momentum balance gives (MomentumBalance::addShedProducts).
  void holdMeanShedProducts(size_t i, const Wrench& end, const Vec3& end_com);

 private:
  friend class AirStage;
  void buildBatch();

  std::vector<AeroBody> bodies_;
  bool active_ = false;
  // Scratch of the added mass's velocity products (world/fluid_stage.cpp), per link.
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> link_velocity_, link_bias_;
  Vec3 flow_ = Vec3::Zero();  // the fluid's velocity in the last (sub)step
  bool flow_known_ = false;
  // The pressure law on all the aero bodies at once (those it holds), and the fluid stage's
  // scratch: per aero body, its kinematics and its wrench from the batch.
  PressureBatch pressure_;
  std::vector<BodyKinematics> kinematics_;
  std::vector<Wrench> batch_wrench_;
};

}  // namespace flapsim
