// The model's link frames from URDF links: full inertia tensors (principal frames) and
// massless links lumped across fixed joints. Private to flapsim_core.
#pragma once

#include <set>
#include <string>

#include "flapsim/creature_model.h"

namespace flapsim {

/// Sets `link`'s mass properties from its URDF <inertial> (`ixx`..`izz` about the COM in the
/// frame rotated by `inertial_rotation` from the link's URDF frame): the principal moments in
/// link.inertia, and link.urdf_frame (identity, exactly, when the tensor is diagonal in the
/// URDF frame). link.com stays in the URDF frame (see expressInLinkFrames). Throws ModelError
/// naming the link if the tensor is not positive definite or its principal moments violate
/// the triangle inequality.
void setInertia(LinkModel& link, const Quat& inertial_rotation, const double (&tensor)[6],
                const std::string& source);

/// Lumps every link without mass (mass 0) on a fixed joint into the link it is fixed to
/// (CreatureModel::lumped), re-rooting the tree at the first link with mass fixed to a
/// massless root. Everything in URDF link frames. Throws ModelError naming a massless link
/// that moves on a joint, a massless root without a link with mass fixed to it, and an
/// <aero> element (`aero_links`) on a lumped link.
void lumpMasslessLinks(CreatureModel& model, const std::set<std::string>& aero_links,
                       const std::string& source);

/// Re-expresses each rotated link's COM, shapes, aero span and joints (read in URDF frames)
/// in its link frame (LinkModel::urdf_frame).
void expressInLinkFrames(CreatureModel& model);

}  // namespace flapsim
