// The air stage of a step: the aero bodies of a creature and the air wrenches applied to
// them once per step. Private to flapsim_core.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/spatial.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/world.h"
#include "fluid/added_mass.h"

namespace flapsim {

struct CreatureBody;

// A link that the air acts on (aero enabled, with boxes); other links have none.
struct AeroBody {
  int link = 0;       // model link index (0 = root = Bullet base)
  std::string model;  // the link's own air model, empty for the world's
  AeroSurface surface;
  // The fluid's implicit part (flapsim/fluid_inertia.h), spatial, about the COM: the added
  // mass of the link's plates at density 1 in body axes, and its factor; this step's added
  // mass (factored) and step x linearised drag, in world axes.
  Mat6 added_mass = Mat6::Zero();
  SpatialFactor added_factor;
  bool has_added_mass = false;  // added_mass is not zero
  SpatialFactor added;          // empty unless has_added_mass
  // What `added` was turned with (CreatureBody::turnedAddedMass): the link's rotation and
  // the density; not valid after a new surface.
  Mat3 added_rotation = Mat3::Zero();
  double added_density = 0.0;
  bool added_valid = false;
  Mat6 drag = Mat6::Zero();
  bool drag_zero = true;  // drag is zero (kept so without rewriting it each step)
  double mass = 0.0;      // the link's own (a lower bound of its effective mass in the tree)
  double area = 0.0;      // of all its air-facing cells
  LinkAero last;          // the wrench of the last step
};

// A drag rate (kg/s) above this many link masses per step is treated implicitly.
constexpr double kImplicitDragRatio = 2.0;

// Whether the drag on aero body `a` is stiff enough for the implicit treatment: if step x
// rho Cd A |u|max / m (A: all its cells, |u|max: its fastest point relative to the air,
// reach: from its COM to its farthest corner) exceeds kImplicitDragRatio. With at most
// about half of a body's cells advancing, that bounds step x (d|F|/du) / m by 1, half of
// the 2 at which the explicit step reverses a face-on cell's normal speed. Below it the
// drag is explicit, first order, cheaper, and more accurate than its linearisation across
// a stroke's turn.
bool needsImplicitDrag(const AeroBody& a, const BodyKinematics& kin, const AirParams& air,
                       double reach, double step);

// The added mass of a link's plate-like boxes at density 1 (AeroBody::added_mass).
Mat6 linkAddedMass(const LinkModel& l, const AirParams& air);

// The aero bodies of a creature, in link order.
std::vector<AeroBody> makeAeroBodies(const CreatureModel& m, const AirParams& air);

// Rebuilds the surfaces of `aero` for new air parameters, keeping everything else.
void resurface(std::vector<AeroBody>& aero, const CreatureModel& m, const AirParams& air);

// The air models in use: the world's default and the built-in ones that links may name.
class AirStage {
 public:
  explicit AirStage(const std::string& default_model);

  void setDefaultModel(AirModelPtr model) { default_model_ = std::move(model); }
  void setRecordCells(bool on) { record_cells_ = on; }

  // Adds this step's air wrench (and buoyancy) to every aero body of `b`, and records it in
  // the body's AeroBody::last. Needs the link frames of b.updateKinematics().
  // `step`: the (sub)step the wrenches act over.
  void apply(CreatureBody& b, const WorldParams& params, double step) const;

 private:
  const AirModel& modelOf(const AeroBody& a) const;

  AirModelPtr default_model_;
  std::map<std::string, AirModelPtr> named_models_;  // for links that name their own
  bool record_cells_ = false;
};

}  // namespace flapsim
