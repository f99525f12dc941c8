#include "model/urdf_numbers.h"

#include <cmath>
#include <cstdlib>
#include <iterator>
#include <locale>
#include <sstream>
#include <vector>

#include "flapsim/creature_model.h"
#include "model/model_error.h"

namespace flapsim {

namespace {

// The numbers an element may carry, checked on the XML before urdfdom (which drops a
// <collision> whose numbers it cannot read, and passes on NaN, inf and 1e300): each listed
// attribute, where present, must hold `count` finite numbers within [low, high].
struct NumberRule {
  const char* path;  // child elements from the link or joint, '/'-separated
  const char* attr;
  int count;
  double low, high;
  const char* what;  // the range in words
};

constexpr double kHuge = kHugeUrdfValue;

const NumberRule kLinkRules[] = {
    {"inertial/origin", "xyz", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 m"},
    {"inertial/origin", "rpy", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 rad"},
    {"inertial/mass", "value", 1, 0.0, kMaxUrdfMass, "in [0, 1e6] kg"},
    {"inertial/inertia", "ixx", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
    {"inertial/inertia", "iyy", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
    {"inertial/inertia", "izz", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
    {"inertial/inertia", "ixy", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
    {"inertial/inertia", "ixz", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
    {"inertial/inertia", "iyz", 1, -kMaxUrdfInertia, kMaxUrdfInertia, "within +-1e6 kg m^2"},
};
// Under each <collision> and <visual>.
const NumberRule kShapeRules[] = {
    {"origin", "xyz", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 m"},
    {"origin", "rpy", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 rad"},
    {"geometry/box", "size", 3, 0.0, kMaxUrdfLength, "in (0, 1000] m"},
    {"geometry/cylinder", "radius", 1, 0.0, kMaxUrdfLength, "in (0, 1000] m"},
    {"geometry/cylinder", "length", 1, 0.0, kMaxUrdfLength, "in (0, 1000] m"},
    {"geometry/sphere", "radius", 1, 0.0, kMaxUrdfLength, "in (0, 1000] m"},
};
const NumberRule kJointRules[] = {
    {"origin", "xyz", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 m"},
    {"origin", "rpy", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000 rad"},
    {"axis", "xyz", 3, -kMaxUrdfLength, kMaxUrdfLength, "within +-1000"},
    {"limit", "lower", 1, -kHuge, kHuge, "within +-1e9"},
    {"limit", "upper", 1, -kHuge, kHuge, "within +-1e9"},
    {"limit", "effort", 1, 0.0, kHuge, "in [0, 1e9]"},
    {"limit", "velocity", 1, 0.0, kHuge, "in [0, 1e9]"},
    {"dynamics", "damping", 1, 0.0, kHuge, "in [0, 1e9]"},
    {"dynamics", "friction", 1, 0.0, kHuge, "in [0, 1e9]"},
};

// Every element at `path` below `e` ('/'-separated names), in document order.
void findAll(const tinyxml2::XMLElement* e, const std::string& path,
             std::vector<const tinyxml2::XMLElement*>& out) {
  const size_t slash = path.find('/');
  const std::string first = path.substr(0, slash);
  for (auto* c = e->FirstChildElement(first.c_str()); c; c = c->NextSiblingElement(first.c_str())) {
    if (slash == std::string::npos) {
      out.push_back(c);
    } else {
      findAll(c, path.substr(slash + 1), out);
    }
  }
}

void checkNumbers(const tinyxml2::XMLElement* e, const NumberRule* rules, size_t n,
                  const std::string& where, const std::string& source) {
  for (size_t r = 0; r < n; ++r) {
    const NumberRule& rule = rules[r];
    std::vector<const tinyxml2::XMLElement*> found;
    findAll(e, rule.path, found);
    for (const tinyxml2::XMLElement* x : found) {
      const char* text = x->Attribute(rule.attr);
      if (!text) continue;
      std::istringstream in(text);
      in.imbue(std::locale::classic());
      std::string word;
      int count = 0;
      bool ok = true;
      while (in >> word) {
        ++count;
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        ok = ok && end && *end == '\0' && std::isfinite(v) && v >= rule.low && v <= rule.high;
      }
      if (!ok || count != rule.count) {
        std::string tag = "<" + std::string(rule.path) + " " + rule.attr + "='" + text + "'>";
        fail(source, where + ": " + tag + " must be " + std::to_string(rule.count) +
                         (rule.count == 1 ? " finite number " : " finite numbers ") + rule.what);
      }
    }
  }
}

}  // namespace

// The numbers of every <link> and <joint> of `robot` (see NumberRule).
void checkAllNumbers(const tinyxml2::XMLElement* robot, const std::string& source) {
  for (auto* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    const char* name = l->Attribute("name");
    const std::string where = "link '" + std::string(name ? name : "") + "'";
    checkNumbers(l, kLinkRules, std::size(kLinkRules), where, source);
    for (const char* shape : {"collision", "visual"}) {
      for (auto* c = l->FirstChildElement(shape); c; c = c->NextSiblingElement(shape)) {
        checkNumbers(c, kShapeRules, std::size(kShapeRules), where + " <" + shape + ">", source);
      }
    }
  }
  for (auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const std::string where = "joint '" + std::string(name ? name : "") + "'";
    checkNumbers(j, kJointRules, std::size(kJointRules), where, source);
  }
}

}  // namespace flapsim
