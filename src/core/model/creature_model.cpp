#include "flapsim/creature_model.h"

#include <console_bridge/console.h>
#include <sys/stat.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <locale>
#include <map>
#include <mutex>
#include <queue>
#include <sstream>

#include "flapsim/air_model.h"

namespace flapsim {

Pose poseFromXyzRpy(const Vec3& xyz, const Vec3& rpy) {
  Quat q = Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Vec3::UnitX());
  return Pose{xyz, q.normalized()};
}

int CreatureModel::findLink(const std::string& link_name) const {
  for (size_t i = 0; i < links.size(); ++i) {
    if (links[i].name == link_name) return static_cast<int>(i);
  }
  return -1;
}

int CreatureModel::findJoint(const std::string& joint_name) const {
  for (size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name == joint_name) return static_cast<int>(i);
  }
  return -1;
}

double CreatureModel::totalMass() const {
  double m = 0.0;
  for (const auto& l : links) m += l.mass;
  return m;
}

namespace {

// Collects what urdfdom reports through console_bridge while it parses, so
// that its reasons (which link, which joint) reach our exception message.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!text_.empty()) text_ += "; ";
      text_ += text;
    }
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

std::mutex& parserMutex() {
  static std::mutex m;
  return m;
}

Pose toPose(const urdf::Pose& p) {
  return Pose{Vec3(p.position.x, p.position.y, p.position.z),
              Quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized()};
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw ModelError(source + ": " + what);
}

void addBoxes(const urdf::LinkConstSharedPtr& link, LinkModel& out) {
  auto add = [&](const urdf::GeometrySharedPtr& g, const urdf::Pose& origin) {
    if (!g || g->type != urdf::Geometry::BOX) return;
    auto box = std::static_pointer_cast<urdf::Box>(g);
    out.boxes.push_back(Box{Vec3(box->dim.x, box->dim.y, box->dim.z), toPose(origin)});
  };
  for (const auto& c : link->collision_array) add(c->geometry, c->origin);
  if (out.boxes.empty()) {
    for (const auto& v : link->visual_array) add(v->geometry, v->origin);
  }
}

double parseDoubleAttr(const tinyxml2::XMLElement* e, const char* attr, const std::string& where,
                       const std::string& source) {
  double value = 0.0;
  if (e->QueryDoubleAttribute(attr, &value) != tinyxml2::XML_SUCCESS || !std::isfinite(value)) {
    fail(source, where + ": attribute '" + attr + "' is not a number");
  }
  return value;
}

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

constexpr double kHuge = 1e9;  // efforts, speeds, damping, friction: any sane value fits

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

// Reads <wing joint=.../> and <aero link=.../> and the document order of joints.
struct Annotations {
  std::vector<std::string> joint_order;
  std::vector<std::string> wings;
  std::vector<std::string> feathers;  // per wing, "" if none
  std::map<std::string, AeroSettings> aero;
  struct Spring {
    std::string joint;
    double stiffness = 0.0, reference = 0.0;
  };
  std::vector<Spring> springs;
  struct Motor {
    std::string joint;
    std::optional<double> stall_torque, no_load_speed;
    double max_power = 0.0;
  };
  std::vector<Motor> motors;
};

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
  for (auto* w = robot->FirstChildElement("wing"); w; w = w->NextSiblingElement("wing")) {
    const char* joint = w->Attribute("joint");
    if (!joint || !*joint) fail(source, "<wing> without a joint attribute");
    a.wings.push_back(joint);
    const char* feather = w->Attribute("feather_joint");
    a.feathers.push_back(feather ? feather : "");
  }
  for (auto* e = robot->FirstChildElement("spring"); e; e = e->NextSiblingElement("spring")) {
    const char* joint = e->Attribute("joint");
    if (!joint || !*joint) fail(source, "<spring> without a joint attribute");
    const std::string where = std::string("<spring joint='") + joint + "'>";
    if (!e->Attribute("stiffness")) fail(source, where + ": no stiffness");
    Annotations::Spring s;
    s.joint = joint;
    s.stiffness = parseDoubleAttr(e, "stiffness", where, source);
    if (s.stiffness < 0.0 || s.stiffness > kHuge) {
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
      if (v < 0.0 || v > kHuge) fail(source, where + ": " + attr + " must be in [0, 1e9]");
      return v;
    };
    m.stall_torque = value("stall_torque");
    m.no_load_speed = value("no_load_speed");
    m.max_power = value("max_power").value_or(0.0);
    a.motors.push_back(m);
  }
  for (auto* e = robot->FirstChildElement("aero"); e; e = e->NextSiblingElement("aero")) {
    const char* link = e->Attribute("link");
    if (!link || !*link) fail(source, "<aero> without a link attribute");
    const std::string where = std::string("<aero link='") + link + "'>";
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
    if (!a.aero.emplace(link, s).second)
      fail(source, "two <aero> elements for link '" + std::string(link) + "'");
  }
  return a;
}

}  // namespace

CreatureModelPtr parseCreatureModel(const std::string& urdf_xml, const std::string& source) {
  Annotations notes = readAnnotations(urdf_xml, source);

  urdf::ModelInterfaceSharedPtr urdf;
  std::string urdf_messages;
  {
    std::lock_guard<std::mutex> lock(parserMutex());
    CapturingHandler handler;
    console_bridge::useOutputHandler(&handler);
    try {
      urdf = urdf::parseURDF(urdf_xml);
    } catch (const std::exception& e) {
      handler.log(e.what(), console_bridge::CONSOLE_BRIDGE_LOG_ERROR, "", 0);
    }
    console_bridge::restorePreviousOutputHandler();
    urdf_messages = handler.text();
  }
  if (!urdf) {
    fail(source, "invalid URDF" + (urdf_messages.empty() ? std::string() : ": " + urdf_messages));
  }

  auto model = std::make_shared<CreatureModel>();
  model->name = urdf->getName();
  model->source = source;

  // Links parent-before-child (breadth first from the root).
  std::map<std::string, int> link_index;
  std::queue<urdf::LinkConstSharedPtr> todo;
  todo.push(urdf->getRoot());
  while (!todo.empty()) {
    urdf::LinkConstSharedPtr l = todo.front();
    todo.pop();
    LinkModel lm;
    lm.name = l->name;
    const std::string where = "link '" + l->name + "'";
    if (l == urdf->getRoot() && l->name == "world") {
      model->fixed_base = true;
      link_index[l->name] = 0;
      model->links.push_back(lm);
      for (const auto& c : l->child_links) todo.push(c);
      continue;
    }
    if (!l->inertial || !(l->inertial->mass > 0.0)) {
      fail(source, where + " has no positive mass (<inertial><mass value=.../>)");
    }
    const auto& in = *l->inertial;
    lm.mass = in.mass;
    Pose com = toPose(in.origin);
    lm.com = com.position;
    if (!com.orientation.isApprox(Quat::Identity(), 1e-12) &&
        !com.orientation.isApprox(Quat(-1, 0, 0, 0), 1e-12)) {
      fail(source, where + ": rotated <inertial><origin rpy> is not supported");
    }
    if (in.ixy != 0.0 || in.ixz != 0.0 || in.iyz != 0.0) {
      fail(source, where + ": off-diagonal inertia (ixy, ixz, iyz) is not supported");
    }
    lm.inertia = Vec3(in.ixx, in.iyy, in.izz);
    if (!finite(lm.inertia) || !finite(lm.com) || !std::isfinite(lm.mass) ||
        lm.inertia.minCoeff() <= 0.0) {
      fail(source, where + ": inertia must be finite and positive");
    }
    addBoxes(l, lm);
    for (const Box& b : lm.boxes) {
      if (!finite(b.size) || b.size.minCoeff() <= 0.0) {
        fail(source, where + ": box size must be positive");
      }
    }
    auto aero = notes.aero.find(l->name);
    if (aero != notes.aero.end()) {
      lm.aero = aero->second;
      notes.aero.erase(aero);
    }
    link_index[l->name] = static_cast<int>(model->links.size());
    model->links.push_back(lm);
    for (const auto& c : l->child_links) todo.push(c);
  }
  if (!notes.aero.empty()) {
    fail(source, "<aero> names unknown link '" + notes.aero.begin()->first + "'");
  }

  // Joints in document order.
  for (const std::string& jname : notes.joint_order) {
    urdf::JointConstSharedPtr j = urdf->getJoint(jname);
    if (!j) continue;
    const std::string where = "joint '" + jname + "'";
    JointModel jm;
    jm.name = jname;
    switch (j->type) {
      case urdf::Joint::FIXED:
        jm.type = JointType::kFixed;
        break;
      case urdf::Joint::REVOLUTE:
        jm.type = JointType::kRevolute;
        break;
      case urdf::Joint::CONTINUOUS:
        jm.type = JointType::kContinuous;
        break;
      case urdf::Joint::PRISMATIC:
        jm.type = JointType::kPrismatic;
        break;
      default:
        fail(source, where + ": type not supported (use fixed, revolute, continuous or prismatic)");
    }
    const auto parent = link_index.find(j->parent_link_name);
    const auto child = link_index.find(j->child_link_name);
    if (parent == link_index.end() || child == link_index.end() || child->second == 0) {
      fail(source, where + ": links '" + j->parent_link_name + "' -> '" + j->child_link_name +
                       "' are not a parent and child in the tree from the root link");
    }
    jm.parent_link = parent->second;
    jm.child_link = child->second;
    jm.origin = toPose(j->parent_to_joint_origin_transform);
    jm.axis = Vec3(j->axis.x, j->axis.y, j->axis.z);
    if (jm.movable()) {
      if (!finite(jm.axis) || jm.axis.norm() < 1e-9) fail(source, where + ": axis is zero");
      jm.axis.normalize();
    }
    if (j->limits) {
      jm.effort = j->limits->effort;
      jm.velocity = j->limits->velocity;
      if (jm.type == JointType::kRevolute || jm.type == JointType::kPrismatic) {
        jm.limited = true;
        jm.lower = j->limits->lower;
        jm.upper = j->limits->upper;
        if (!(jm.lower <= jm.upper)) fail(source, where + ": lower limit above upper limit");
      }
    }
    if (j->dynamics) {
      jm.damping = j->dynamics->damping;
      jm.friction = j->dynamics->friction;
      if (jm.damping < 0.0 || jm.friction < 0.0) {
        fail(source, where + ": damping and friction must be >= 0");
      }
    }
    model->links[jm.child_link].parent_joint = static_cast<int>(model->joints.size());
    model->joints.push_back(jm);
  }

  for (size_t wi = 0; wi < notes.wings.size(); ++wi) {
    const std::string& w = notes.wings[wi];
    int idx = model->findJoint(w);
    if (idx < 0) fail(source, "<wing> names unknown joint '" + w + "'");
    JointModel& jm = model->joints[idx];
    if (jm.type != JointType::kRevolute && jm.type != JointType::kContinuous) {
      fail(source, "<wing joint='" + w + "'>: a wing joint must be revolute or continuous");
    }
    if (jm.wing) fail(source, "joint '" + w + "' is marked <wing> twice");
    jm.wing = true;
    if (!notes.feathers[wi].empty()) {
      const std::string& f = notes.feathers[wi];
      const int fi = model->findJoint(f);
      if (fi < 0) fail(source, "<wing joint='" + w + "'> names unknown feather_joint '" + f + "'");
      if (model->joints[fi].type != JointType::kRevolute &&
          model->joints[fi].type != JointType::kContinuous) {
        fail(source, "feather_joint '" + f + "' must be revolute or continuous");
      }
      if (fi == idx) fail(source, "<wing joint='" + w + "'> names itself as its feather_joint");
      jm.feather_joint = fi;
    }
  }
  for (const Annotations::Spring& s : notes.springs) {
    const int idx = model->findJoint(s.joint);
    if (idx < 0) fail(source, "<spring> names unknown joint '" + s.joint + "'");
    JointModel& jm = model->joints[idx];
    if (!jm.movable()) fail(source, "<spring joint='" + s.joint + "'>: the joint is fixed");
    if (jm.stiffness > 0.0) fail(source, "joint '" + s.joint + "' has two <spring> elements");
    jm.stiffness = s.stiffness;
    jm.reference = s.reference;
  }
  for (const Annotations::Motor& m : notes.motors) {
    const int idx = model->findJoint(m.joint);
    if (idx < 0) fail(source, "<motor> names unknown joint '" + m.joint + "'");
    JointModel& jm = model->joints[idx];
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
  for (size_t i = 0; i < model->joints.size(); ++i) {
    if (model->joints[i].wing) model->wing_joints.push_back(static_cast<int>(i));
  }
  return model;
}

std::optional<Vec3> spanAxis(const CreatureModel& model, int link) {
  const LinkModel& l = model.links.at(static_cast<size_t>(link));
  if (l.parent_joint >= 0) {
    const JointModel& j = model.joints[l.parent_joint];
    if (j.wing) {
      // The joint's axis passes through the link frame's origin (URDF: joint frame = child
      // link frame), along j.axis: the span runs from that line out to the COM.
      const Vec3 out = l.com - l.com.dot(j.axis) * j.axis;
      if (out.norm() > 1e-9) return Vec3(out.normalized());
    }
    for (int w : model.wing_joints) {
      if (model.joints[w].feather_joint == l.parent_joint) return j.axis;
    }
  }
  return l.aero.span;
}

std::string readUrdfFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw ModelError(path + ": cannot open file");
  if (!S_ISREG(info.st_mode)) throw ModelError(path + ": not a regular file");
  if (static_cast<std::uintmax_t>(info.st_size) > kMaxUrdfFileBytes) {
    throw ModelError(path + ": " + std::to_string(info.st_size) + " bytes, over the limit of " +
                     std::to_string(kMaxUrdfFileBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path + ": cannot open file");
  // In chunks, stopping past the limit: the file may have grown since stat().
  std::string text;
  text.reserve(static_cast<size_t>(info.st_size));
  char chunk[65536];
  while (text.size() <= kMaxUrdfFileBytes && in.read(chunk, sizeof chunk).gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
  }
  if (text.size() > kMaxUrdfFileBytes) {
    throw ModelError(path + ": over the limit of " + std::to_string(kMaxUrdfFileBytes) + " bytes");
  }
  return text;
}

CreatureModelPtr loadCreatureModel(const std::string& path) {
  return parseCreatureModel(readUrdfFile(path), path);
}

}  // namespace flapsim
