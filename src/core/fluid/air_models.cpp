// The registry of air models: one line per built-in law, and the laws registerAirModel adds.
#include <mutex>

#include "fluid/fluid_law.h"
#include "fluid/pressure.h"
#include "fluid/quasi_steady.h"

namespace flapsim {

namespace {

struct Registry {
  std::mutex mutex;
  std::vector<std::pair<std::string, AirModelPtr>> laws;
};

Registry& registry() {
  static Registry r{{},
                    {
                        {"pressure", std::make_shared<PressureAirModel>()},
                        {"quasi_steady", std::make_shared<QuasiSteadyAirModel>()},
                    }};
  return r;
}

}  // namespace

AirDamping AirModel::dragDamping(const BodyKinematics& /*body*/, const AeroSurface& /*surface*/,
                                 const AirParams& /*air*/) const {
  return AirDamping::Zero();
}

double AirModel::forceCoefficient(const AeroSurface& surface, const AirParams& /*air*/) const {
  return surface.drag_coefficient;
}

std::string AirModel::check(const AirParams& /*air*/) const { return ""; }

AirModelPtr makeAirModel(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& law : r.laws) {
    if (law.first == name) return law.second;
  }
  return nullptr;
}

void registerAirModel(const std::string& name, AirModelPtr model) {
  if (name.empty()) throw InputError("air model: the name is empty");
  if (!model) throw InputError("air model '" + name + "' is null");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& law : r.laws) {
    if (law.first == name) throw InputError("air model '" + name + "' is already registered");
  }
  r.laws.emplace_back(name, std::move(model));
}

std::vector<std::string> airModelNames() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& law : r.laws) names.push_back(law.first);
  return names;
}

const char* addedMassProductsName(AddedMassProducts products) {
  switch (products) {
    case AddedMassProducts::kOmitted:
      return "omitted";
    case AddedMassProducts::kKirchhoff:
      return "kirchhoff";
    case AddedMassProducts::kShed:
      return "shed";
  }
  return "?";
}

std::vector<std::string> addedMassProductsNames() { return {"omitted", "kirchhoff", "shed"}; }

AddedMassProducts parseAddedMassProducts(const std::string& name) {
  for (AddedMassProducts p :
       {AddedMassProducts::kOmitted, AddedMassProducts::kKirchhoff, AddedMassProducts::kShed}) {
    if (name == addedMassProductsName(p)) return p;
  }
  throw InputError("unknown added-mass products '" + name + "' (omitted, kirchhoff, shed)");
}

std::string unknownAirModelMessage(const std::string& name) {
  std::string list;
  for (const std::string& n : airModelNames()) list += (list.empty() ? "" : ", ") + n;
  return "unknown air model '" + name + "' (" + list + ")";
}

std::string checkAirModels(const AirParams& air) {
  std::vector<AirModelPtr> laws;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    for (const auto& law : r.laws) laws.push_back(law.second);
  }
  for (const AirModelPtr& law : laws) {
    std::string err = law->check(air);
    if (!err.empty()) return err;
  }
  return "";
}

bool batchedPressureLaw(const AirModel& model) {
  static const AirModel* const pressure = makeAirModel("pressure").get();
  return &model == pressure;
}

}  // namespace flapsim
