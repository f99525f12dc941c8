// A seeded mutation fuzzer over the shipped URDFs, through the parser and a world: every
// mutant is either refused with a ModelError or InputError that names its source or
// creature, or it spawns and steps with a finite state (a diverging one frozen by the
// watchdog, which names it). Same seed, same cases: a failure replays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Values that broke parsers and worlds: non-numbers, signs, zero, huge and tiny magnitudes,
// huge grids, wrong counts, empty text.
const char* const kValues[] = {
    "nan",
    "NaN",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e300",
    "-1e300",
    "1e-300",
    "1e200",
    "1e200 1e200 1e200",
    "nan 0 0",
    "0 0 inf",
    "1000 1000",
    "100000 100000",
    "0 0",
    "-1 -1",
    "1 2",
    "",
    "abc",
    "1 2 3 4",
    "0.35 0.35 0.35",
    "true",
    "2",
    "-0.35",
    "1e9",
    "world",
    "unit0_body",
    "unit0_wing_left_joint",
};

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::string mutate(std::string text) {
    const int n = 1 + static_cast<int>(pick(3));
    for (int i = 0; i < n; ++i) {
      switch (pick(4)) {
        case 0:
        case 1:
          text = replaceValue(text);
          break;
        case 2:
          text = dropLine(text);
          break;
        default:
          text = duplicateLine(text);
          break;
      }
    }
    return text;
  }

 private:
  size_t pick(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }

  // An attribute value (between =" and ") replaced by a listed value or a scaled number.
  std::string replaceValue(const std::string& text) {
    std::vector<size_t> starts;
    for (size_t at = text.find("=\""); at != std::string::npos; at = text.find("=\"", at + 2)) {
      starts.push_back(at + 2);
    }
    if (starts.empty()) return text;
    const size_t begin = starts[pick(starts.size())];
    const size_t end = text.find('"', begin);
    if (end == std::string::npos) return text;
    std::string value;
    if (pick(4) == 0) {
      std::ostringstream os;
      os << std::uniform_real_distribution<double>(-1e4, 1e4)(rng_);
      value = os.str();
    } else {
      value = kValues[pick(std::size(kValues))];
    }
    return text.substr(0, begin) + value + text.substr(end);
  }

  std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
  static std::string join(const std::vector<std::string>& ls) {
    std::string out;
    for (const std::string& l : ls) out += l + "\n";
    return out;
  }
  // A missing element (or half of one: malformed XML is a case too).
  std::string dropLine(const std::string& text) {
    std::vector<std::string> ls = lines(text);
    if (ls.size() < 3) return text;
    ls.erase(ls.begin() + 1 + static_cast<long>(pick(ls.size() - 2)));
    return join(ls);
  }
  // A duplicated tag.
  std::string duplicateLine(const std::string& text) {
    std::vector<std::string> ls = lines(text);
    if (ls.size() < 3) return text;
    const size_t i = 1 + pick(ls.size() - 2);
    ls.insert(ls.begin() + static_cast<long>(i), ls[i]);
    return join(ls);
  }

  std::mt19937_64 rng_;
};

bool finiteState(const CreatureState& s) {
  for (size_t k = 0; k < s.link_poses.size(); ++k) {
    if (!s.link_poses[k].position.allFinite() || !s.link_poses[k].orientation.coeffs().allFinite())
      return false;
    if (!s.link_twists[k].linear.allFinite() || !s.link_twists[k].angular.allFinite()) return false;
  }
  for (double q : s.joint_positions) {
    if (!std::isfinite(q)) return false;
  }
  for (double v : s.joint_velocities) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

struct Tally {
  int cases = 0, model_errors = 0, input_errors = 0, stepped = 0, frozen = 0;
};

// One mutant: parsed, spawned, stepped 50 steps with its wings commanded; the assertions
// say which case (the seed and index replay it).
void runCase(const std::string& urdf, int index, Tally& t) {
  ++t.cases;
  const std::string source = "mutant_" + std::to_string(index) + ".urdf";
  CreatureModelPtr model;
  try {
    model = parseCreatureModel(urdf, source);
  } catch (const ModelError& e) {
    ++t.model_errors;
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(source + ": ", 0), 0u) << "case " << index << ": " << what;
    EXPECT_GT(what.size(), source.size() + 2) << "case " << index;
    return;
  }
  WorldParams p;
  World w(p);
  try {
    w.spawn("c", model, test::at(0, 0, 2));
    if (!model->wing_joints.empty()) {
      w.setWingCommands("c", {},
                        std::vector<StrokeCommand>(model->wing_joints.size(), {40, 10, 0.3}));
    }
  } catch (const InputError& e) {
    ++t.input_errors;
    EXPECT_NE(std::string(e.what()).find("'c'"), std::string::npos)
        << "case " << index << ": " << e.what();
    return;
  }
  ++t.stepped;
  // Step by step: a mutant that diverges must be frozen at the state before the step the
  // watchdog refused (bit for bit), at that step, with the link named; one that does not
  // must stay finite in every number of its state (joint rates too, which the watchdog does
  // not read).
  CreatureState before = w.state("c");
  for (int step = 1; step <= 50; ++step) {
    w.step(1);
    const CreatureState now = w.state("c");
    if (const std::optional<Divergence> d = w.divergence("c")) {
      ++t.frozen;
      EXPECT_EQ(d->creature, "c") << "case " << index;
      EXPECT_EQ(d->step, static_cast<std::uint64_t>(step)) << "case " << index;
      EXPECT_NE(d->quantity.find("link '"), std::string::npos) << "case " << index;
      CreatureState kept = before;  // a frozen creature's efforts are zero
      kept.joint_efforts.assign(kept.joint_efforts.size(), 0.0);
      EXPECT_TRUE(test::bitIdentical(kept, now)) << "case " << index << ": " << d->quantity;
      return;
    }
    EXPECT_TRUE(finiteState(now)) << "case " << index << " step " << step << "\n" << urdf;
    before = now;
  }
}

// 6,000 mutants of six shipped creatures (seed 15), each stepped 50 steps: in CI time (under
// a second here), and each class of outcome is reached.
TEST(UrdfFuzz, MutantsAreRefusedByNameOrStepFiniteOrFreezeAtTheirLastState) {
  const char* files[] = {"plate.urdf",        "flap_unit.urdf",     "afc_1.urdf",
                         "feather_unit.urdf", "bamboo_copter.urdf", "swimmer.urdf"};
  std::vector<std::string> texts;
  for (const char* f : files) texts.push_back(readText(test::sourcePath(std::string("urdf/") + f)));
  Mutator m(15);
  Tally t;
  for (int i = 0; i < 6000; ++i) {
    const std::string urdf = m.mutate(texts[static_cast<size_t>(i) % texts.size()]);
    try {
      runCase(urdf, i, t);
    } catch (const std::exception& e) {  // neither ModelError nor InputError: unnamed
      ADD_FAILURE() << "case " << i << ": " << e.what() << "\n" << urdf;
    }
    if (::testing::Test::HasFailure()) break;  // the first failing case says enough
  }
  std::printf("urdf fuzz: %d cases: %d model errors, %d spawn errors, %d stepped (%d frozen)\n",
              t.cases, t.model_errors, t.input_errors, t.stepped, t.frozen);
  EXPECT_EQ(t.cases, 6000);
  EXPECT_GT(t.model_errors, 0);
  EXPECT_GT(t.stepped, 0);
}

}  // namespace
}  // namespace flapsim
