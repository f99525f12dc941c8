// mujoco_bench: a reference for bench/flapsim_bench.cpp. It times THE SAME flapping creatures
// (flapsim::makeCreatureUrdf with 1, 4, 6, 12 and 25 units) in MuJoCo (any version from 2.2.2:
// Debian's, or a newer one built against by bench/vs_mujoco.sh) and prints the median steps per
// second of mj_step, the real-time factor and the cost per body per step; it prints figures and
// never passes or fails on time. Mapping: flapsim's own CreatureModel is turned into MJCF, one
// body per link nested as the joint tree (frames from JointModel::origin, the root free at
// z = 50 with no floor), inertial from the link mass, COM and principal moments (link axes), one
// box geom per LinkModel box (half sizes) with MuJoCo's ellipsoid fluid model in air (density
// 1.204, viscosity 0) and contype = conaffinity = 0 (flapsim has no self-collision), hinges with
// their axis, limits as range, damping, and the <spring> stiffness and reference; gravity
// -9.81 z. Every wing hinge gets a velocity actuator (kv below, force range = the URDF effort)
// whose target is set each step by flapsim::StrokeGenerator from the joint angle and the step
// (the mean velocity of the ideal stroke over the step, as flapsim's drives take it), with
// strokes of 30/10 rad/s and amplitude 0.8 rad, as flapsim_bench does. Only the stepping loop
// (controller included) is timed.
//
//   mujoco_bench [--runs 5] [--seconds 2] [--only NAME] [--cpu-time]
//                [--integrator implicit] [--step 0.001] [--jacobian auto] [--check T]
//                [--reference-step S] [--mjcf]
//
// --integrator: Euler, RK4, implicit or implicitfast (what the MuJoCo in use knows; its own
// parser refuses the rest). --step: the time step, s. --jacobian: dense, sparse or auto.
// --check T: instead of timing, the stability probe of each creature at that setting: T
// simulated seconds (not timed), MuJoCo's warnings, non-finite velocities, the largest joint
// speed |qvel|, the root's height change after 3 s and the first wing's stroke range, against the
// same creature at RK4 with --reference-step S (1/16 ms: see kReferenceStep); then "verdict:
// stable" or "verdict: UNSTABLE (why)". --mjcf: print the MJCF of each creature at that setting
// instead (MuJoCo is not opened).
#include <dlfcn.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "bench_common.h"
#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"
#include "flapsim/stroke.h"
#include "mujoco_api.h"

using flapsim_bench::mj;

namespace {

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
// the wing). Every version and integrator gets the same kv: the same creature.
constexpr double kWingKv = 0.1;
const flapsim::StrokeCommand kStroke{30.0, 10.0, 0.8};

// How MuJoCo steps: integrator and Jacobian as MJCF spells them, the step in s.
struct Setting {
  std::string integrator = "implicit";
  double step = 0.001;  // s, as flapsim's WorldParams::step_size by default
  std::string jacobian = "auto";
};

// The reference a setting is checked against: RK4 at `step` (--reference-step), by default
// 1/16 ms. RK4 at 0.25 ms (the reference of the MuJoCo 3.12 peer kit, on its own heavier
// creature) is itself unstable on flapsim's creatures, with their 4 g wing plates: in MuJoCo
// 3.12 it spins the flap unit's wing up to 206 rad/s within 60 ms (0.125 ms: 66 rad/s, the
// strokes' own top speed being 27). At 1/16 ms the height change after 3 s is within 0.02%
// (flap unit) and 0.5% (12-unit chain) of RK4's at 1/32 ms (mujoco_bench --check 10 --integrator
// RK4 --step 0.0000625 --reference-step 0.00003125).
constexpr double kReferenceStep = 0.0000625;
Setting referenceSetting(const Setting& s, double step) { return Setting{"RK4", step, s.jacobian}; }

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
      out << " damping=\"" << j.damping << "\" frictionloss=\"" << j.friction << '"';
      if (j.stiffness > 0.0) {
        out << " stiffness=\"" << j.stiffness << "\" springref=\"" << j.reference << '"';
      }
      out << "/>\n";
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

// MJCF text of `model` stepped as `s` says, with a velocity actuator on each wing hinge.
std::string toMjcf(const flapsim::CreatureModel& model, const Setting& s) {
  std::vector<std::vector<int>> children(model.links.size());
  for (const flapsim::JointModel& j : model.joints) children[j.parent_link].push_back(j.child_link);
  std::ostringstream out;
  out << std::setprecision(12);
  out << "<mujoco model=\"" << model.name << "\">\n"
      << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "  <option timestep=\"" << s.step << "\" gravity=\"0 0 -9.81\" integrator=\""
      << s.integrator << "\" jacobian=\"" << s.jacobian
      << "\" density=\"1.204\" viscosity=\"0\"/>\n"
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
  ~Creature() {
    if (model) mj.deleteModel(model);
  }
};

// flapsim's model of a benchmark creature.
flapsim::CreatureModelPtr creatureModel(const flapsim_bench::BenchCreature& b) {
  return flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(b.units, "c"));
}

std::unique_ptr<Creature> build(const flapsim_bench::BenchCreature& b, const Setting& s) {
  const flapsim::CreatureModelPtr cm = creatureModel(b);
  auto c = std::make_unique<Creature>();
  c->xml = toMjcf(*cm, s);
  c->bodies = static_cast<int>(cm->links.size());
  c->model = flapsim_bench::compileMjcf(c->xml);
  for (int u = 0; u < c->model->nu; ++u) {
    c->wing_qpos.push_back(c->model->jnt_qposadr[c->model->actuator_trnid[2 * u]]);
  }
  return c;
}

int stepsOf(double seconds, double step) {
  return std::max(1, static_cast<int>(seconds / step + 0.5));
}

struct RunResult {
  double steps_per_second = 0.0;
  double root_height = 0.0;               // at the end
  int strokes = 0;                        // completed down-up cycles of the first wing
  double min_wing = 0.0, max_wing = 0.0;  // range of the first wing's angle, rad
  // The stability probe's figures (run(..., probe = true) only).
  int warnings = 0;                       // MuJoCo's warning counters, summed
  bool finite = true;                     // every qvel stayed finite
  double max_qvel = 0.0;                  // the largest |qvel| of any degree of freedom
  int max_dof = -1;                       // its degree of freedom
  double max_time = 0.0;                  // and when, s
  double late_min = 0.0, late_max = 0.0;  // the first wing's range over the second half
  double early_height = 0.0;              // the root's at kHeightTime (or the end, if sooner)
  double early_time = 0.0;                // when that was, s
};

// When the probe compares heights: the flights stay predictable up to about then (over 10 s
// the 12-unit chain's is not: RK4 at 1/16 and 1/32 ms end 0.9 m apart, as flapsim's own
// chain at 1 and 1/8 ms drifts apart after 5 s), while a blow-up or spin-up shows in the
// speeds over the whole probe.
constexpr double kHeightTime = 3.0;  // s

// One run: fresh mjData, `steps` steps with the stroke controller, timed. With `probe`, also
// the largest |qvel| and the second half's stroke range after every step (for --check; the
// timing then means nothing).
RunResult run(const Creature& c, int steps, bool probe = false) {
  mjData* d = mj.makeData(c.model);
  std::vector<flapsim::StrokeGenerator> gens(c.wing_qpos.size());
  for (flapsim::StrokeGenerator& g : gens) g.setCommand(kStroke);
  const int nu = static_cast<int>(gens.size());
  const int nv = c.model->nv;
  const double step = c.model->opt.timestep;
  int switches = 0;
  bool was_up = false;
  RunResult r;
  r.late_min = 1e300;
  r.late_max = -1e300;
  double lo = 0.0, hi = 0.0;
  const double t0 = flapsim_bench::benchSeconds();
  for (int i = 0; i < steps; ++i) {
    for (int u = 0; u < nu; ++u) d->ctrl[u] = gens[u].target(d->qpos[c.wing_qpos[u]], step);
    if (nu > 0) {
      const double q = d->qpos[c.wing_qpos[0]];
      lo = std::min(lo, q);
      hi = std::max(hi, q);
      const bool up = gens[0].phase() == flapsim::StrokeGenerator::Phase::kUp;
      if (up != was_up) ++switches;
      was_up = up;
    }
    mj.step(c.model, d);
    if (!probe) continue;
    if (i + 1 == std::min(steps, stepsOf(kHeightTime, step))) {
      r.early_height = d->qpos[2];
      r.early_time = d->time;
    }
    for (int v = 0; v < nv; ++v) {
      const double speed = std::abs(d->qvel[v]);
      if (!std::isfinite(speed)) r.finite = false;
      if (speed > r.max_qvel) {
        r.max_qvel = speed;
        r.max_dof = v;
        r.max_time = d->time;
      }
    }
    if (nu > 0 && 2 * i >= steps) {
      r.late_min = std::min(r.late_min, d->qpos[c.wing_qpos[0]]);
      r.late_max = std::max(r.late_max, d->qpos[c.wing_qpos[0]]);
    }
  }
  r.steps_per_second = steps / (flapsim_bench::benchSeconds() - t0);
  r.root_height = d->qpos[2];
  r.strokes = switches / 2;
  r.min_wing = lo;
  r.max_wing = hi;
  for (int w = 0; w < mjNWARNING; ++w) r.warnings += d->warning[w].number;
  mj.deleteData(d);
  return r;
}

std::string describe(const Setting& s) {
  char text[128];
  std::snprintf(text, sizeof(text), "%s, %g ms, %s Jacobian", s.integrator.c_str(), s.step * 1e3,
                s.jacobian.c_str());
  return text;
}

// The verdict (flapsim_bench::instability()) on MuJoCo's figures.
std::string instability(const RunResult& r, const RunResult& ref) {
  auto figures = [](const RunResult& x) {
    return flapsim_bench::ProbeFigures{x.warnings, x.finite, x.max_qvel,
                                       x.early_height - kStartHeight};
  };
  return flapsim_bench::instability(figures(r), figures(ref), "MuJoCo warning(s)", "max |qvel|");
}

void printProbe(const char* label, const Setting& s, const RunResult& r) {
  std::printf(
      "  %-9s %-32s warnings %d, %s, max |qvel| %.4g (dof %d at %.3f s), height change %.4f m "
      "after %g s (%.4f m at the end), %d strokes, first wing in [%.3f, %.3f] rad over the second "
      "half\n",
      label, describe(s).c_str(), r.warnings, r.finite ? "finite" : "NON-FINITE", r.max_qvel,
      r.max_dof, r.max_time, r.early_height - kStartHeight, r.early_time,
      r.root_height - kStartHeight, r.strokes, r.late_min, r.late_max);
}

// --check: the probe of `b` at `s` and at the reference; prints both and the verdict.
// Returns false if the creature could not be built.
bool check(const flapsim_bench::BenchCreature& b, const Setting& s, double seconds,
           double reference_step) {
  const Setting ref = referenceSetting(s, reference_step);
  std::unique_ptr<Creature> c, r;
  try {
    c = build(b, s);
    r = build(b, ref);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mujoco_bench: %s: %s\n", b.name.c_str(), e.what());
    return false;
  }
  const RunResult at = run(*c, stepsOf(seconds, s.step), true);
  const RunResult against = run(*r, stepsOf(seconds, ref.step), true);
  std::printf("%s, %g s simulated:\n", b.name.c_str(), seconds);
  printProbe("setting", s, at);
  printProbe("reference", ref, against);
  const std::string why = instability(at, against);
  std::printf("  verdict: %s%s%s\n", why.empty() ? "stable" : "UNSTABLE (", why.c_str(),
              why.empty() ? "" : ")");
  return true;
}

// The options of mujoco_bench beyond the reference benchmarks' own.
struct MujocoOptions {
  Setting setting;
  double check_seconds = 0.0;  // > 0: --check
  double reference_step = kReferenceStep;
  bool print_mjcf = false;
};

// Takes --integrator, --step, --jacobian, --check, --reference-step and --mjcf out of argv
// (the rest stays for parseBenchOptions). False on a missing or bad value.
bool takeMujocoOptions(int& argc, char** argv, MujocoOptions* o) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--integrator" && has_value) {
      o->setting.integrator = argv[++i];
    } else if (a == "--jacobian" && has_value) {
      o->setting.jacobian = argv[++i];
    } else if (a == "--step" && has_value) {
      if (!flapsim_bench::parseSeconds(argv[++i], &o->setting.step) || o->setting.step > 1.0) {
        return false;
      }
    } else if (a == "--check" && has_value) {
      if (!flapsim_bench::parseSeconds(argv[++i], &o->check_seconds)) return false;
    } else if (a == "--reference-step" && has_value) {
      if (!flapsim_bench::parseSeconds(argv[++i], &o->reference_step) || o->reference_step > 1.0) {
        return false;
      }
    } else if (a == "--mjcf") {
      o->print_mjcf = true;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  MujocoOptions m;
  flapsim_bench::BenchOptions o;
  if (!takeMujocoOptions(argc, argv, &m) || !flapsim_bench::parseBenchOptions(argc, argv, &o)) {
    std::fprintf(stderr,
                 "  MuJoCo: [--integrator Euler|RK4|implicit|implicitfast] [--step S] "
                 "[--jacobian dense|sparse|auto] [--check T] [--reference-step S] [--mjcf]\n");
    return flapsim_bench::referenceUsage("mujoco_bench");
  }
  const Setting& setting = m.setting;
  if (m.print_mjcf) {
    for (const flapsim_bench::BenchCreature& b : flapsim_bench::benchCreatures()) {
      if (!o.only.empty() && b.name != o.only) continue;
      std::printf("<!-- %s -->\n%s", b.name.c_str(), toMjcf(*creatureModel(b), setting).c_str());
    }
    return 0;
  }
  if (!flapsim_bench::openMujoco(FLAPSIM_MUJOCO_LIBRARY, "mujoco_bench")) return 1;
  *mj.user_warning = flapsim_bench::warningToStderr;
  if (m.check_seconds > 0.0) {
    std::printf("mujoco_bench: MuJoCo %s, stability of %s against %s\n", mj.versionString(),
                describe(setting).c_str(),
                describe(referenceSetting(setting, m.reference_step)).c_str());
    for (const flapsim_bench::BenchCreature& b : flapsim_bench::benchCreatures()) {
      if (!o.only.empty() && b.name != o.only) continue;
      if (!check(b, setting, m.check_seconds, m.reference_step)) return 1;
    }
    return 0;
  }
  const int steps = stepsOf(o.seconds, setting.step);
  std::printf(
      "mujoco_bench: MuJoCo %s, %s, %d runs of %g s simulated (%d steps of %g ms), medians\n",
      mj.versionString(), describe(setting).c_str(), o.runs, steps * setting.step, steps,
      setting.step * 1e3);
  flapsim_bench::printTableHeader();
  bool have_unit = false;
  RunResult unit;
  for (const flapsim_bench::BenchCreature& b : flapsim_bench::benchCreatures()) {
    if (!o.only.empty() && b.name != o.only) continue;
    std::unique_ptr<Creature> c;
    try {
      c = build(b, setting);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mujoco_bench: %s: %s\n", b.name.c_str(), e.what());
      return 1;
    }
    std::vector<double> sps;
    RunResult last;
    for (int r = 0; r < o.runs; ++r) {
      last = run(*c, steps);
      sps.push_back(last.steps_per_second);
    }
    flapsim_bench::printTableRow(b.name, c->bodies, flapsim_bench::median(sps), setting.step);
    if (b.units == 1) {
      have_unit = true;
      unit = last;
    }
  }
  if (have_unit) {
    std::printf(
        "flap_unit: root height %.3f m after %g s from %.0f m; %d strokes, left wing angle in "
        "[%.3f, %.3f] rad\n",
        unit.root_height, steps * setting.step, kStartHeight, unit.strokes, unit.min_wing,
        unit.max_wing);
  }
  return 0;
}
