// mujoco_bench: a reference for bench/flapsim_bench.cpp. It times THE SAME flapping creatures
// (flapsim::makeCreatureUrdf with 1, 4, 6, 12 and 25 units) in MuJoCo 2.2.2 and prints the
// median steps per second of mj_step, the real-time factor and the cost per body per step; it
// prints figures and never passes or fails on time. Mapping: flapsim's own CreatureModel is
// turned into MJCF, one body per link nested as the joint tree (frames from JointModel::origin,
// the root free at z = 50 with no floor), inertial from the link mass, COM and principal moments
// (link axes), one box geom per LinkModel box (half sizes) with MuJoCo's ellipsoid fluid model in
// air (density 1.204, viscosity 0) and contype = conaffinity = 0 (flapsim has no self-collision),
// hinges with their axis, limits as range and damping; 1 ms steps, gravity -9.81 z, implicit
// integrator. Every wing hinge gets a velocity actuator (kv below, force range = the URDF
// effort) whose target is set each step by flapsim::StrokeGenerator from the joint angle, with
// strokes of 30/10 rad/s and amplitude 0.8 rad, as flapsim_bench does. Only the stepping loop
// (controller included) is timed.
//
//   mujoco_bench [--runs 5] [--seconds 2] [--only NAME]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_common.h"
#include "mujoco_common.h"
#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"
#include "flapsim/stroke.h"

namespace {

constexpr double kTimestep = 0.001;  // s, as flapsim's WorldParams::step_size
constexpr double kStartHeight = 50.0;
// Velocity-servo gain on the wing hinges, N m s/rad. flapsim's servo reaches the target
// velocity within one step unless that needs more than the effort (2 N m); a wing's inertia
// about its hinge is about 1.6e-4 kg m^2, so a large kv (1 and up, time constant I / kv under
// 0.2 ms) would be the closest copy. But MuJoCo 2.2.2's implicit integrator keeps the actuator's
// -kv velocity derivative in the step even while forcerange clamps the force (later versions skip
// clamped actuators), which makes the wing as sluggish as if its inertia were I + h kv: with
// kv = 1 a 40 rad/s stroke reversal takes about 20 ms and overshoots the amplitude by 0.25 rad.
// kv = 0.1 gave the least tracking error over a flight (within 20% of the new rate about 6 ms
// after a reversal, overshoot 0.06 rad; a steady lag of a few rad/s against MuJoCo's air load on
// the wing).
constexpr double kWingKv = 0.1;
const flapsim::StrokeCommand kStroke{30.0, 10.0, 0.8};

void appendVec(std::ostringstream& out, const char* attr, const flapsim::Vec3& v) {
  out << ' ' << attr << "=\"" << v.x() << ' ' << v.y() << ' ' << v.z() << '"';
}

void appendQuat(std::ostringstream& out, const flapsim::Quat& q) {
  out << " quat=\"" << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << '"';
}

// Appends link `index` and, nested in it, its children.
void appendBody(const flapsim::CreatureModel& model, const std::vector<std::vector<int>>& children,
                int index, int depth, std::ostringstream& out) {
  const flapsim::LinkModel& link = model.links[index];
  const std::string pad(2 * depth + 4, ' ');
  out << pad << "<body name=\"" << link.name << '"';
  if (link.parent_joint < 0) {
    appendVec(out, "pos", flapsim::Vec3(0, 0, kStartHeight));
  } else {
    const flapsim::Pose& origin = model.joints[link.parent_joint].origin;
    appendVec(out, "pos", origin.position);
    appendQuat(out, origin.orientation);
  }
  out << ">\n";
  if (link.parent_joint < 0) {
    if (!model.fixed_base) out << pad << "  <freejoint name=\"root\"/>\n";
  } else {
    const flapsim::JointModel& j = model.joints[link.parent_joint];
    if (j.movable()) {
      out << pad << "  <joint name=\"" << j.name << "\" type=\""
          << (j.type == flapsim::JointType::kPrismatic ? "slide" : "hinge") << '"';
      appendVec(out, "axis", j.axis);
      if (j.limited && j.type != flapsim::JointType::kContinuous) {
        out << " limited=\"true\" range=\"" << j.lower << ' ' << j.upper << '"';
      } else {
        out << " limited=\"false\"";
      }
      out << " damping=\"" << j.damping << "\" frictionloss=\"" << j.friction << "\"/>\n";
    }
  }
  if (link.mass > 0.0) {
    out << pad << "  <inertial";
    appendVec(out, "pos", link.com);
    out << " mass=\"" << link.mass << '"';
    appendVec(out, "diaginertia", link.inertia);
    out << "/>\n";
  }
  for (const flapsim::Box& box : link.boxes) {
    out << pad << "  <geom type=\"box\"";
    appendVec(out, "size", 0.5 * box.size);
    appendVec(out, "pos", box.origin.position);
    appendQuat(out, box.origin.orientation);
    out << " contype=\"0\" conaffinity=\"0\" fluidshape=\"ellipsoid\"/>\n";
  }
  for (int child : children[index]) appendBody(model, children, child, depth + 1, out);
  out << pad << "</body>\n";
}

// MJCF text of `model`, with a velocity actuator on each wing hinge.
std::string toMjcf(const flapsim::CreatureModel& model) {
  std::vector<std::vector<int>> children(model.links.size());
  for (const flapsim::JointModel& j : model.joints) children[j.parent_link].push_back(j.child_link);
  std::ostringstream out;
  out << std::setprecision(12);
  out << "<mujoco model=\"" << model.name << "\">\n"
      << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "  <option timestep=\"" << kTimestep << "\" gravity=\"0 0 -9.81\" integrator=\"implicit\""
      << " density=\"1.204\" viscosity=\"0\"/>\n"
      << "  <worldbody>\n";
  appendBody(model, children, 0, 0, out);
  out << "  </worldbody>\n"
      << "  <actuator>\n";
  for (int w : model.wing_joints) {
    const flapsim::JointModel& j = model.joints[w];
    out << "    <velocity name=\"" << j.name << "_motor\" joint=\"" << j.name << "\" kv=\""
        << kWingKv << '"';
    if (j.effort > 0.0) {
      out << " forcelimited=\"true\" forcerange=\"" << -j.effort << ' ' << j.effort << '"';
    }
    out << "/>\n";
  }
  out << "  </actuator>\n"
      << "</mujoco>\n";
  return out.str();
}

// A compiled creature: its MJCF, the model and the joint of each wing actuator.
struct Creature {
  std::string xml;
  int bodies = 0;  // links of the creature (MuJoCo's world body not counted)
  mjModel* model = nullptr;
  std::vector<int> wing_qpos;  // qpos address of the joint of each actuator
  ~Creature() { mj_deleteModel(model); }
};

std::unique_ptr<Creature> build(const flapsim_bench::BenchCreature& s) {
  const flapsim::CreatureModelPtr cm =
      flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(s.units, "c"));
  auto c = std::make_unique<Creature>();
  c->xml = toMjcf(*cm);
  c->bodies = static_cast<int>(cm->links.size());
  c->model = flapsim_bench::compileMjcf(c->xml);
  for (int u = 0; u < c->model->nu; ++u) {
    c->wing_qpos.push_back(c->model->jnt_qposadr[c->model->actuator_trnid[2 * u]]);
  }
  return c;
}

struct RunResult {
  double steps_per_second = 0.0;
  double root_height = 0.0;               // at the end
  int strokes = 0;                        // completed down-up cycles of the first wing
  double min_wing = 0.0, max_wing = 0.0;  // range of the first wing's angle, rad
};

// One run: fresh mjData, `steps` steps of 1 ms with the stroke controller, timed.
RunResult run(const Creature& c, int steps) {
  mjData* d = mj_makeData(c.model);
  std::vector<flapsim::StrokeGenerator> gens(c.wing_qpos.size());
  for (flapsim::StrokeGenerator& g : gens) g.setCommand(kStroke);
  const int nu = static_cast<int>(gens.size());
  int switches = 0;
  bool was_up = false;
  double lo = 0.0, hi = 0.0;
  const double t0 = flapsim_bench::benchSeconds();
  for (int i = 0; i < steps; ++i) {
    for (int u = 0; u < nu; ++u) d->ctrl[u] = gens[u].target(d->qpos[c.wing_qpos[u]]);
    if (nu > 0) {
      const double q = d->qpos[c.wing_qpos[0]];
      lo = std::min(lo, q);
      hi = std::max(hi, q);
      const bool up = gens[0].phase() == flapsim::StrokeGenerator::Phase::kUp;
      if (up != was_up) ++switches;
      was_up = up;
    }
    mj_step(c.model, d);
  }
  RunResult r;
  r.steps_per_second = steps / (flapsim_bench::benchSeconds() - t0);
  r.root_height = d->qpos[2];
  r.strokes = switches / 2;
  r.min_wing = lo;
  r.max_wing = hi;
  mj_deleteData(d);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  flapsim_bench::BenchOptions o;
  if (!flapsim_bench::parseBenchOptions(argc, argv, &o)) {
    return flapsim_bench::referenceUsage("mujoco_bench");
  }
  mju_user_warning = flapsim_bench::warningToStderr;
  const int steps = std::max(1, static_cast<int>(o.seconds / kTimestep + 0.5));
  std::printf("mujoco_bench: MuJoCo %s, %d runs of %g s simulated (%d steps of %g ms), medians\n",
              mj_versionString(), o.runs, steps * kTimestep, steps, kTimestep * 1e3);
  flapsim_bench::printTableHeader();
  bool have_unit = false;
  RunResult unit;
  for (const flapsim_bench::BenchCreature& s : flapsim_bench::benchCreatures()) {
    if (!o.only.empty() && s.name != o.only) continue;
    std::unique_ptr<Creature> c;
    try {
      c = build(s);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mujoco_bench: %s: %s\n", s.name.c_str(), e.what());
      return 1;
    }
    std::vector<double> sps;
    RunResult last;
    for (int r = 0; r < o.runs; ++r) {
      last = run(*c, steps);
      sps.push_back(last.steps_per_second);
    }
    flapsim_bench::printTableRow(s.name, c->bodies, flapsim_bench::median(sps), kTimestep);
    if (s.units == 1) {
      have_unit = true;
      unit = last;
    }
  }
  if (have_unit) {
    std::printf(
        "flap_unit: root height %.3f m after %g s from %.0f m; %d strokes, left wing angle in "
        "[%.3f, %.3f] rad\n",
        unit.root_height, steps * kTimestep, kStartHeight, unit.strokes, unit.min_wing,
        unit.max_wing);
  }
  return 0;
}
