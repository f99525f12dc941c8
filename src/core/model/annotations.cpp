#include "model/annotations.h"

#include <tinyxml2.h>

#include <cmath>
#include <optional>
#include <sstream>

#include "flapsim/air_model.h"
#include "model/model_error.h"
#include "model/urdf_numbers.h"

namespace flapsim {

namespace {

double parseDoubleAttr(const tinyxml2::XMLElement* e, const char* attr, const std::string& where,
                       const std::string& source) {
  double value = 0.0;
  if (e->QueryDoubleAttribute(attr, &value) != tinyxml2::XML_SUCCESS || !std::isfinite(value)) {
    fail(source, where + ": attribute '" + attr + "' is not a number");
  }
  return value;
}

void readWings(const tinyxml2::XMLElement* robot, const std::string& source, Annotations& a) {
  for (auto* w = robot->FirstChildElement("wing"); w; w = w->NextSiblingElement("wing")) {
    const char* joint = w->Attribute("joint");
    if (!joint || !*joint) fail(source, "<wing> without a joint attribute");
    a.wings.push_back(joint);
    const char* feather = w->Attribute("feather_joint");
    a.feathers.push_back(feather ? feather : "");
  }
}

void readSprings(const tinyxml2::XMLElement* robot, const std::string& source, Annotations& a) {
  for (auto* e = robot->FirstChildElement("spring"); e; e = e->NextSiblingElement("spring")) {
    const char* joint = e->Attribute("joint");
    if (!joint || !*joint) fail(source, "<spring> without a joint attribute");
    const std::string where = std::string("<spring joint='") + joint + "'>";
    if (!e->Attribute("stiffness")) fail(source, where + ": no stiffness");
    Annotations::Spring s;
    s.joint = joint;
    s.stiffness = parseDoubleAttr(e, "stiffness", where, source);
    if (s.stiffness < 0.0 || s.stiffness > kHugeUrdfValue) {
      fail(source, where + ": stiffness must be in [0, 1e9]");
    }
    if (e->Attribute("reference")) {
      s.reference = parseDoubleAttr(e, "reference", where, source);
      if (std::abs(s.reference) > kMaxUrdfLength) {
        fail(source, where + ": reference must be within +-1000");
      }
    }
    a.springs.push_back(s);
  }
}

void readMotors(const tinyxml2::XMLElement* robot, const std::string& source, Annotations& a) {
  for (auto* e = robot->FirstChildElement("motor"); e; e = e->NextSiblingElement("motor")) {
    const char* joint = e->Attribute("joint");
    if (!joint || !*joint) fail(source, "<motor> without a joint attribute");
    const std::string where = std::string("<motor joint='") + joint + "'>";
    Annotations::Motor m;
    m.joint = joint;
    // A non-negative number within 1e9, if the attribute is there.
    auto value = [&](const char* attr) -> std::optional<double> {
      if (!e->Attribute(attr)) return std::nullopt;
      const double v = parseDoubleAttr(e, attr, where, source);
      if (v < 0.0 || v > kHugeUrdfValue) {
        fail(source, where + ": " + attr + " must be in [0, 1e9]");
      }
      return v;
    };
    m.stall_torque = value("stall_torque");
    m.no_load_speed = value("no_load_speed");
    m.max_power = value("max_power").value_or(0.0);
    a.motors.push_back(m);
  }
}

// Sets the motors of `model`'s joints from `notes` (defaults from the joints' <limit>).
void applyMotors(const Annotations& notes, const std::string& source, CreatureModel& model) {
  for (const Annotations::Motor& m : notes.motors) {
    const int idx = model.findJoint(m.joint);
    if (idx < 0) fail(source, "<motor> names unknown joint '" + m.joint + "'");
    JointModel& jm = model.joints[idx];
    const std::string where = "<motor joint='" + m.joint + "'>";
    if (!jm.movable()) fail(source, where + ": the joint is fixed");
    if (jm.motor) fail(source, "joint '" + m.joint + "' has two <motor> elements");
    MotorSpec spec;
    spec.stall_torque = m.stall_torque.value_or(jm.effort);
    if (!(spec.stall_torque > 0.0)) {
      fail(source, where + ": needs a stall_torque > 0 (or the joint's <limit effort>)");
    }
    spec.no_load_speed = m.no_load_speed.value_or(jm.velocity);
    spec.max_power = m.max_power;
    jm.motor = spec;
  }
}

// One <aero link=...> element's settings.
AeroSettings readAero(const tinyxml2::XMLElement* e, const std::string& where,
                      const std::string& source) {
  AeroSettings s;
  if (e->Attribute("drag_coefficient")) {
    double cd = parseDoubleAttr(e, "drag_coefficient", where, source);
    if (cd < 0.0 || cd > 1e3) fail(source, where + ": drag_coefficient must be in [0, 1000]");
    s.drag_coefficient = cd;
  }
  if (const char* sub = e->Attribute("subdivisions")) {
    std::istringstream in(sub);
    int nu = 0, nv = 0;
    std::string rest;
    if (!(in >> nu >> nv) || (in >> rest) || nu < 1 || nv < 1 || nu > 1000 || nv > 1000) {
      fail(source, where + ": subdivisions must be two integers in 1..1000, got '" + sub + "'");
    }
    s.subdivisions_u = nu;
    s.subdivisions_v = nv;
  }
  if (const char* model = e->Attribute("model")) {
    if (!makeAirModel(model)) {
      fail(source, where + ": " + unknownAirModelMessage(model));
    }
    s.model = model;
  }
  if (const char* span = e->Attribute("span")) {
    const std::string v(span);
    if (v == "x") {
      s.span = Vec3::UnitX();
    } else if (v == "y") {
      s.span = Vec3::UnitY();
    } else if (v == "z") {
      s.span = Vec3::UnitZ();
    } else {
      fail(source, where + ": span must be x, y or z, got '" + v + "'");
    }
  }
  // A boolean attribute: true/1 or false/0, else an error naming it.
  auto flag = [&](const char* name) -> std::optional<bool> {
    const char* text = e->Attribute(name);
    if (!text) return std::nullopt;
    const std::string v(text);
    if (v == "true" || v == "1") return true;
    if (v == "false" || v == "0") return false;
    fail(source, where + ": " + name + " must be true or false, got '" + v + "'");
  };
  if (const std::optional<bool> en = flag("enabled")) s.enabled = *en;
  s.added_mass = flag("added_mass");
  return s;
}

// One <collision_mesh link=...> element's settings.
Annotations::CollisionMesh readCollisionMesh(const tinyxml2::XMLElement* e,
                                             const std::string& where, const std::string& source) {
  Annotations::CollisionMesh c;
  for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
    const std::string name = a->Name();
    if (name != "link" && name != "optimization" && name != "max_convex_hulls") {
      fail(source, where + ": unknown attribute '" + name +
                       "' (it has link, optimization and max_convex_hulls)");
    }
  }
  const char* optimization = e->Attribute("optimization");
  const std::string v = optimization ? optimization : "convex_hull";
  if (v == "convex_decomposition") {
    c.decompose = true;
  } else if (v != "convex_hull") {
    fail(source,
         where + ": optimization must be convex_hull or convex_decomposition, got '" + v + "'");
  }
  if (const char* text = e->Attribute("max_convex_hulls")) {
    if (!c.decompose) {
      fail(source, where + ": max_convex_hulls is for optimization='convex_decomposition' only");
    }
    std::istringstream in(text);
    int n = 0;
    std::string rest;
    if (!(in >> n) || (in >> rest) || n < 1 || n > kMaxConvexHulls) {
      fail(source, where + ": max_convex_hulls must be an integer in 1.." +
                       std::to_string(kMaxConvexHulls) + ", got '" + text + "'");
    }
    c.max_convex_hulls = n;
  }
  return c;
}

void readCollisionMeshes(const tinyxml2::XMLElement* robot, const std::string& source,
                         Annotations& a) {
  for (auto* e = robot->FirstChildElement("collision_mesh"); e;
       e = e->NextSiblingElement("collision_mesh")) {
    const char* link = e->Attribute("link");
    if (!link || !*link) fail(source, "<collision_mesh> without a link attribute");
    const std::string where = std::string("<collision_mesh link='") + link + "'>";
    if (!a.collision_meshes.emplace(link, readCollisionMesh(e, where, source)).second) {
      fail(source, "two <collision_mesh> elements for link '" + std::string(link) + "'");
    }
  }
}

}  // namespace

Annotations readAnnotations(const std::string& xml, const std::string& source) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    fail(source, std::string("malformed XML: ") + (doc.ErrorStr() ? doc.ErrorStr() : "?"));
  }
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) fail(source, "no <robot> element");
  checkAllNumbers(robot, source);
  Annotations a;
  for (auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    if (const char* n = j->Attribute("name")) a.joint_order.push_back(n);
  }
  readWings(robot, source, a);
  readSprings(robot, source, a);
  readMotors(robot, source, a);
  readCollisionMeshes(robot, source, a);
  for (auto* e = robot->FirstChildElement("aero"); e; e = e->NextSiblingElement("aero")) {
    const char* link = e->Attribute("link");
    if (!link || !*link) fail(source, "<aero> without a link attribute");
    const AeroSettings s = readAero(e, std::string("<aero link='") + link + "'>", source);
    if (!a.aero.emplace(link, s).second) {
      fail(source, "two <aero> elements for link '" + std::string(link) + "'");
    }
  }
  return a;
}

void applyJointAnnotations(const Annotations& notes, const std::string& source,
                           CreatureModel& model) {
  for (size_t wi = 0; wi < notes.wings.size(); ++wi) {
    const std::string& w = notes.wings[wi];
    int idx = model.findJoint(w);
    if (idx < 0) fail(source, "<wing> names unknown joint '" + w + "'");
    JointModel& jm = model.joints[idx];
    if (jm.type != JointType::kRevolute && jm.type != JointType::kContinuous) {
      fail(source, "<wing joint='" + w + "'>: a wing joint must be revolute or continuous");
    }
    if (jm.wing) fail(source, "joint '" + w + "' is marked <wing> twice");
    jm.wing = true;
    if (!notes.feathers[wi].empty()) {
      const std::string& f = notes.feathers[wi];
      const int fi = model.findJoint(f);
      if (fi < 0) fail(source, "<wing joint='" + w + "'> names unknown feather_joint '" + f + "'");
      if (model.joints[fi].type != JointType::kRevolute &&
          model.joints[fi].type != JointType::kContinuous) {
        fail(source, "feather_joint '" + f + "' must be revolute or continuous");
      }
      if (fi == idx) fail(source, "<wing joint='" + w + "'> names itself as its feather_joint");
      jm.feather_joint = fi;
    }
  }
  for (const Annotations::Spring& s : notes.springs) {
    const int idx = model.findJoint(s.joint);
    if (idx < 0) fail(source, "<spring> names unknown joint '" + s.joint + "'");
    JointModel& jm = model.joints[idx];
    if (!jm.movable()) fail(source, "<spring joint='" + s.joint + "'>: the joint is fixed");
    if (jm.stiffness > 0.0) fail(source, "joint '" + s.joint + "' has two <spring> elements");
    jm.stiffness = s.stiffness;
    jm.reference = s.reference;
  }
  applyMotors(notes, source, model);
  for (size_t i = 0; i < model.joints.size(); ++i) {
    if (model.joints[i].wing) model.wing_joints.push_back(static_cast<int>(i));
  }
}

}  // namespace flapsim
