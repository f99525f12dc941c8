#include "dynamics/implicit_fluid.h"

#include <vector>

#include "dynamics/bullet_body.h"
#include "fluid/creature_fluid.h"

namespace flapsim {

const ServoLoads& ImplicitFluidLoads::loads(
    const std::vector<AeroBody>& aero, const LinkFrames& frames, size_t links,
    const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& change_of_link) {
  // Only the aero bodies with implicit drag or added mass have loads (loads_.links).
  loads_.extra_inertia.resize(links);
  loads_.impulse.resize(links);
  loads_.links.clear();
  drag_.resize(aero.size());
  change_.resize(aero.size());
  for (size_t i = 0; i < aero.size(); ++i) {
    const int k = aero[i].link;
    change_[i] = change_of_link[k];
    if (aero[i].drag_zero && !aero[i].has_added_mass) continue;
    loads_.links.push_back(k);
    const Vec3 offset = fromBt(frames.com(k) - frames.com(0));
    Mat6& extra = loads_.extra_inertia[k];
    extra.setZero();
    if (!aero[i].drag_zero) {
      drag_[i] = spatialToCommonFrame(aero[i].drag, Quat::Identity(), offset);
      extra += drag_[i];
    }
    if (aero[i].has_added_mass) addFactorMatrix(aero[i].added, offset, extra);
    loads_.impulse[k] = -extra * change_[i];
  }
  return loads_;
}

Vec6 ImplicitFluidLoads::dragImpulses(const std::vector<AeroBody>& aero,
                                      const ServoSolution& solution) {
  Vec6 drag_impulse = Vec6::Zero();
  drag_impulse_.assign(aero.size(), Vec6::Zero());
  for (size_t i = 0; i < aero.size(); ++i) {
    if (aero[i].drag_zero) continue;
    drag_impulse_[i] = -drag_[i] * (change_[i] + solution.link_velocity_change[aero[i].link]);
    drag_impulse += drag_impulse_[i];
  }
  return drag_impulse;
}

}  // namespace flapsim
