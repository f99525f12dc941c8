// Service request fields under gazebo_msgs' names (model_name, model_xml, link_name,
// body_name) and under this package's former ones (name, urdf_xml, link), kept one release:
// a request may give either; both set must agree. A link field may also name its creature,
// "<creature>::<link>", as gazebo's link_name and body_name do. Pure functions, tested
// without a master.
#pragma once

#include <string>

#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/DeleteCreature.h"
#include "flapsim/GetState.h"
#include "flapsim/SetState.h"
#include "flapsim/SpawnCreature.h"

namespace flapsim_ros {

/// A request field: its name and value.
struct RequestField {
  const char* name;
  const std::string& value;
};

/// The value of a field under two names, gazebo_msgs' `current` and the former `old`:
/// whichever is set. InputError naming both if both are set and differ.
std::string eitherField(const RequestField& current, const RequestField& old);

/// The creature and link a request names.
struct RequestBody {
  std::string creature;
  std::string link;  // empty: the root link
};

/// The creature (`model`, `old_model`: eitherField) and link (`link`, `old_link`) of a
/// request. The link may be "<creature>::<link>": its creature then is the request's (the
/// model fields empty) or must be the one they name. InputError naming the fields otherwise.
RequestBody requestBody(const RequestField& model, const RequestField& old_model,
                        const RequestField& link, const RequestField& old_link);

/// Puts the creature, link (and, for a spawn, URDF text) a request names, under either name,
/// into its former fields (`name`, `link`, `urdf_xml`), which the node reads. InputError
/// naming the fields if they disagree.
void adoptGazeboNames(flapsim::SpawnCreature::Request& req);
void adoptGazeboNames(flapsim::DeleteCreature::Request& req);
void adoptGazeboNames(flapsim::GetState::Request& req);
void adoptGazeboNames(flapsim::SetState::Request& req);
void adoptGazeboNames(flapsim::ApplyWrench::Request& req);
void adoptGazeboNames(flapsim::ClearWrenches::Request& req);

}  // namespace flapsim_ros
