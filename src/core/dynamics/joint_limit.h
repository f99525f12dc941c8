// Joint limits for Bullet's multibody constraint solvers that hold. Private to flapsim_core.
//
// Bullet's btMultiBodyJointLimitConstraint has two flaws that together make limits give way:
// it writes the upper bound's Jacobian on its "B" side, which the MLCP (Dantzig) solver does
// not couple with other rows of the same multibody (so wings resting on their upper limits
// are solved as if each were alone: each row over-corrects, and the error grows step by step
// until the creature blows up), and it only acts once a joint has passed its bound (so a
// wing striking its stop at speed goes past it by a step's travel or more).
//
// JointLimits holds every limit of one multibody. Each limit has one row, for its nearer
// bound, on the multibody's own side: the joint may close the gap to the bound within the
// step but not cross it (a speculative row), and a joint already beyond is pushed back at
// the solver's error reduction rate. While any joint could reach a bound in this step, the
// rows of all limits are solved together (an impulse on one joint moves the others); while
// none can, there are no rows and no solve. With near rows only (a lean step's choice), only
// the joints that could reach a bound get rows; if the solve then sends one of the others
// towards its bound (omittedMayReach), the step restores the velocities and solves again with
// every row. Rows for every limit cost the 12-unit chain, whose wings turn within two steps'
// travel of their stops, more than half its time in closed-loop flight.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <vector>

namespace flapsim {

class JointLimits : public btMultiBodyConstraint {
 public:
  struct Limit {
    int link = 0;  // Bullet link of the joint
    btScalar lower = 0, upper = 0;
  };

  // `limits` (at least one) of the joints of `body`.
  JointLimits(btMultiBody* body, std::vector<Limit> limits);

  // Whether any joint could reach one of its bounds within a step of `dt` at its current
  // velocity: only then does the limit have rows (createConstraintRows).
  bool mayAct(btScalar dt) const;

  // Rows only for the joints that could reach a bound (true), or for all (false, the default).
  void setNearRowsOnly(bool on) { near_rows_only_ = on; }
  // Whether a joint left without a row by the last createConstraintRows could now (with the
  // solve's velocities) reach a bound within a step of `dt`.
  bool omittedMayReach(btScalar dt) const;

  void finalizeMultiDof() override;
  int getIslandIdA() const override;
  int getIslandIdB() const override;
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void debugDraw(btIDebugDraw*) override {}

 private:
  // Whether `l`'s joint could reach its nearer bound within a step of `dt`.
  bool mayReach(const Limit& l, btScalar dt) const;

  std::vector<Limit> limits_;
  bool near_rows_only_ = false;
  std::vector<char> omitted_;  // per limit: no row in the last createConstraintRows
};

}  // namespace flapsim
