#include "flapsim/body_genome.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>

namespace flapsim {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

}  // namespace

std::string validateMassBudget(const MassBudget& b) {
  const std::pair<const char*, double> fields[] = {
      {"payload", b.payload},
      {"wing_areal_density", b.wing_areal_density},
      {"spar_linear_density", b.spar_linear_density},
      {"motor_specific_power", b.motor_specific_power}};
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value) || !(value > 0.0)) {
      return std::string("mass budget: ") + name + " must be a positive number, got " +
             number(value);
    }
  }
  return "";
}

const std::vector<BodyGene>& bodyGenes() {
  using P = HoverParams;
  static const std::vector<BodyGene> genes = {
      {"wing_span", &P::wing_span, 0.06, 0.24, "m"},
      {"wing_chord", &P::wing_chord, 0.02, 0.09, "m"},
      {"stroke_limit", &P::stroke_limit, 0.6, 1.5, "rad"},
      {"max_power", &P::max_power, 0.05, 6.0, "W"},
      {"no_load_speed", &P::no_load_speed, 50.0, 600.0, "rad/s"},
      {"hinge_stiffness", &P::hinge_stiffness, 0.0, 0.1, "N m/rad"},
      {"body_mass", &P::body_mass, 0.008, 0.05, "kg"},
      {"com_drop", &P::com_drop, 0.0, 0.05, "m"},
      {"hinge_below_top", &P::hinge_below_top, 0.005, 0.065, "m"}};
  return genes;
}

std::string checkBodyGenes(const std::vector<double>& genes) {
  if (genes.size() != static_cast<size_t>(kBodyGeneCount)) {
    return std::to_string(genes.size()) + " genes, a body genome has " +
           std::to_string(kBodyGeneCount);
  }
  for (size_t i = 0; i < genes.size(); ++i) {
    if (!std::isfinite(genes[i]) || std::abs(genes[i]) > kBodyGeneRange) {
      return "gene " + std::to_string(i) + " (" + bodyGenes()[i].name + ") is " + number(genes[i]) +
             ", not a number in [-1, 1]";
    }
  }
  return "";
}

HoverParams bodyFromGenes(const std::vector<double>& genes, const MassBudget& budget) {
  const std::string err = checkBodyGenes(genes);
  if (!err.empty()) throw InputError("body genome: " + err);
  HoverParams p;
  for (size_t i = 0; i < genes.size(); ++i) {
    const BodyGene& g = bodyGenes()[i];
    p.*g.member = g.min + 0.5 * (genes[i] + 1.0) * (g.max - g.min);
  }
  p.wing_mass = budget.wing_areal_density * p.wing_span * p.wing_chord;
  p.spar_mass = budget.spar_linear_density * p.wing_span;
  p.stall_torque = 4.0 * p.max_power / p.no_load_speed;
  return p;
}

std::vector<double> bodyGenesFromParams(const HoverParams& params) {
  std::vector<double> genes;
  for (const BodyGene& g : bodyGenes()) {
    genes.push_back(2.0 * (params.*g.member - g.min) / (g.max - g.min) - 1.0);
  }
  return genes;
}

BodyMass bodyMass(const HoverParams& p, const MassBudget& budget) {
  BodyMass m;
  m.motors = 2.0 * p.max_power / budget.motor_specific_power;
  m.payload = budget.payload;
  m.ballast = p.body_mass - m.payload - m.motors;
  m.wings = 2.0 * (p.wing_mass + p.spar_mass);
  m.total = p.body_mass + m.wings;
  return m;
}

std::string checkMassBudget(const HoverParams& p, const MassBudget& budget) {
  const BodyMass m = bodyMass(p, budget);
  if (m.ballast >= 0.0) return "";
  std::ostringstream out;
  out << "mass budget does not close: payload " << number(1e3 * m.payload) << " g + motors "
      << number(1e3 * m.motors) << " g (2 x " << number(p.max_power) << " W at "
      << number(budget.motor_specific_power) << " W/kg) exceed body_mass "
      << number(1e3 * p.body_mass) << " g";
  return out.str();
}

BodyBuild buildBody(const std::vector<double>& genes, const MassBudget& budget,
                    const std::string& name) {
  BodyBuild b;
  const std::string prefix = "body '" + name + "': ";
  std::string err = checkBodyGenes(genes);
  if (!err.empty()) {
    b.refusal = prefix + err;
    return b;
  }
  b.params = bodyFromGenes(genes, budget);
  err = validateMassBudget(budget);
  if (err.empty()) err = checkMassBudget(b.params, budget);
  if (!err.empty()) {
    b.refusal = prefix + err;
    return b;
  }
  try {
    std::string urdf = makeHoverUrdf(name, b.params);
    b.model = parseCreatureModel(urdf, "body genome '" + name + "'");
    b.urdf = std::move(urdf);
  } catch (const std::exception& e) {
    b.model.reset();
    b.refusal = prefix + "make_creature refused it: " + e.what();
  }
  return b;
}

}  // namespace flapsim
