#include "flapsim_ros/request_names.h"

#include "flapsim/types.h"
#include "flapsim_ros/params.h"  // validateCreatureName

namespace flapsim_ros {
namespace {

constexpr size_t kQuotedLength = 80;  // longer values (URDF text) are not repeated in refusals

std::string quoted(const RequestField& f) {
  return f.value.size() <= kQuotedLength ? std::string(f.name) + " '" + f.value + "'"
                                         : std::string(f.name);
}

}  // namespace

std::string eitherField(const RequestField& current, const RequestField& old) {
  if (!current.value.empty() && !old.value.empty() && current.value != old.value) {
    throw flapsim::InputError(quoted(current) + " and " + quoted(old) + " differ (" + old.name +
                              " is " + current.name + "'s former name: give one)");
  }
  return current.value.empty() ? old.value : current.value;
}

namespace {

// A link field: "<creature>::<link>" split (a creature name has no ':'), or a link name alone.
RequestBody splitLink(const RequestField& f) {
  const size_t at = f.value.find("::");
  if (at == std::string::npos || !validateCreatureName(f.value.substr(0, at)).empty()) {
    return RequestBody{"", f.value};
  }
  RequestBody b{f.value.substr(0, at), f.value.substr(at + 2)};
  if (b.link.empty()) {
    throw flapsim::InputError(quoted(f) + " names no link (give '" + b.creature +
                              "::<link>', or leave it empty for the root link)");
  }
  return b;
}

}  // namespace

RequestBody requestBody(const RequestField& model, const RequestField& old_model,
                        const RequestField& link, const RequestField& old_link) {
  const RequestBody a = splitLink(link), b = splitLink(old_link);
  // Both given: alike once split ("fu::body" and "body" of model fu are the same link).
  if (!link.value.empty() && !old_link.value.empty() &&
      (a.link != b.link ||
       (!a.creature.empty() && !b.creature.empty() && a.creature != b.creature))) {
    throw flapsim::InputError(quoted(link) + " and " + quoted(old_link) + " differ (" +
                              old_link.name + " is " + link.name + "'s former name: give one)");
  }
  RequestBody body{eitherField(model, old_model), link.value.empty() ? b.link : a.link};
  const RequestField& named = model.value.empty() ? old_model : model;
  for (const auto& [field, split] : {std::make_pair(&link, &a), std::make_pair(&old_link, &b)}) {
    if (split->creature.empty()) continue;
    if (!body.creature.empty() && body.creature != split->creature) {
      throw flapsim::InputError(quoted(*field) + " is a link of '" + split->creature +
                                "', not of " + quoted(named));
    }
    body.creature = split->creature;
  }
  return body;
}

void adoptGazeboNames(flapsim::SpawnCreature::Request& req) {
  req.name = eitherField({"model_name", req.model_name}, {"name", req.name});
  req.urdf_xml = eitherField({"model_xml", req.model_xml}, {"urdf_xml", req.urdf_xml});
}

void adoptGazeboNames(flapsim::DeleteCreature::Request& req) {
  req.name = eitherField({"model_name", req.model_name}, {"name", req.name});
}

namespace {

// A request naming a creature and one of its links: gazebo_msgs' `link_field` (link_name or
// body_name) or the former `link`.
template <class Request>
void adoptBodyNames(Request& req, const char* link_field, const std::string& link_value) {
  const RequestBody b = requestBody({"model_name", req.model_name}, {"name", req.name},
                                    {link_field, link_value}, {"link", req.link});
  req.name = b.creature;
  req.link = b.link;
}

}  // namespace

void adoptGazeboNames(flapsim::GetState::Request& req) {
  adoptBodyNames(req, "link_name", req.link_name);
}

void adoptGazeboNames(flapsim::SetState::Request& req) {
  adoptBodyNames(req, "link_name", req.link_name);
}

void adoptGazeboNames(flapsim::ApplyWrench::Request& req) {
  adoptBodyNames(req, "body_name", req.body_name);
}

void adoptGazeboNames(flapsim::ClearWrenches::Request& req) {
  adoptBodyNames(req, "body_name", req.body_name);
}

}  // namespace flapsim_ros
