// Parameters and messages of the controller nodes, without a master.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "flapsim/ann.h"
#include "flapsim/hover_gains.h"
#include "flapsim_ros/controller_params.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/disturbance_node.h"
#include "flapsim_ros/hover_controller_node.h"

namespace flapsim_ros {
namespace {

XmlRpc::XmlRpcValue yamlish(std::initializer_list<std::pair<std::string, XmlRpc::XmlRpcValue>> kv) {
  XmlRpc::XmlRpcValue v;
  v.begin();  // make it a struct even when empty
  for (const auto& [k, x] : kv) v[k] = x;
  return v;
}

XmlRpc::XmlRpcValue list(std::initializer_list<double> xs) {
  XmlRpc::XmlRpcValue v;
  v.setSize(static_cast<int>(xs.size()));
  int i = 0;
  for (double x : xs) v[i++] = x;
  return v;
}

TEST(StrokeControllerParams, DefaultsNumbersAndPerPairLists) {
  XmlRpc::XmlRpcValue empty;
  const StrokeControllerParams d = parseStrokeControllerParams(empty, "flap_unit");
  EXPECT_EQ(d.creature, "flap_unit");
  ASSERT_EQ(d.strokes.size(), 1u);
  EXPECT_EQ(d.strokes[0].downstroke_rate, 40.0);
  EXPECT_EQ(d.strokes[0].upstroke_rate, 10.0);
  EXPECT_EQ(d.strokes[0].amplitude, 0.8);

  const StrokeControllerParams p =
      parseStrokeControllerParams(yamlish({{"creature", XmlRpc::XmlRpcValue("afc")},
                                           {"pairs", XmlRpc::XmlRpcValue(3)},
                                           {"downstroke_rate", list({30, 35, 40})},
                                           {"upstroke_rate", XmlRpc::XmlRpcValue(12)},
                                           {"amplitude", XmlRpc::XmlRpcValue(1.1)}}),
                                  "ignored");
  EXPECT_EQ(p.creature, "afc");
  ASSERT_EQ(p.strokes.size(), 3u);
  EXPECT_EQ(p.strokes[1].downstroke_rate, 35.0);
  EXPECT_EQ(p.strokes[2].upstroke_rate, 12.0);
  EXPECT_EQ(p.strokes[0].amplitude, 1.1);

  const flapsim::WingCommand msg = strokeCommandMsg(p.strokes);
  EXPECT_TRUE(msg.joint_names.empty());  // all wings in URDF order: left, right per pair
  ASSERT_EQ(msg.downstroke_rate.size(), 6u);
  EXPECT_EQ(msg.downstroke_rate[2], 35.0);
  EXPECT_EQ(msg.downstroke_rate[3], 35.0);
  EXPECT_EQ(msg.upstroke_rate.size(), 6u);
  EXPECT_EQ(msg.amplitude.size(), 6u);
}

TEST(StrokeControllerParams, BadValuesNameTheirKey) {
  auto message = [](const XmlRpc::XmlRpcValue& v) {
    try {
      parseStrokeControllerParams(v, "c");
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(
      message(yamlish({{"pairs", XmlRpc::XmlRpcValue(2)}, {"downstroke_rate", list({30, 35, 40})}}))
          .find("downstroke_rate"),
      std::string::npos);
  EXPECT_NE(message(yamlish({{"upstroke_rate", XmlRpc::XmlRpcValue(-1.0)}})).find("upstroke"),
            std::string::npos);
  EXPECT_NE(message(yamlish({{"amplitude", XmlRpc::XmlRpcValue("wide")}})).find("amplitude"),
            std::string::npos);
  EXPECT_NE(message(yamlish({{"pairs", XmlRpc::XmlRpcValue(0)}})).find("pairs"), std::string::npos);
  EXPECT_NE(message(yamlish({{"creature", XmlRpc::XmlRpcValue("bad name")}})).find("creature"),
            std::string::npos);
  EXPECT_NE(message(yamlish({{"rate", XmlRpc::XmlRpcValue(0.0)}})).find("rate"), std::string::npos);
}

TEST(AnnControllerParams, RequiresWeightsAndReadsLockstep) {
  EXPECT_THROW(parseAnnControllerParams(XmlRpc::XmlRpcValue(), "afc"), ParamError);
  const AnnControllerParams p =
      parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("/tmp/w.yaml")},
                                        {"pairs", XmlRpc::XmlRpcValue(4)},
                                        {"lockstep", XmlRpc::XmlRpcValue(true)},
                                        {"lockstep_duration", XmlRpc::XmlRpcValue(2.5)}}),
                               "afc");
  EXPECT_EQ(p.creature, "afc");
  EXPECT_EQ(p.weights_file, "/tmp/w.yaml");
  EXPECT_EQ(p.pairs, 4);
  EXPECT_TRUE(p.lockstep);
  EXPECT_EQ(p.lockstep_duration, 2.5);
  EXPECT_EQ(p.step_service, "/flapsim/step");
  EXPECT_EQ(p.rate, 0.0);  // from the weights file
  EXPECT_THROW(parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w")},
                                                 {"lockstep", XmlRpc::XmlRpcValue(1)}}),
                                        "afc"),
               ParamError);
  EXPECT_THROW(parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w")}}), ""),
               ParamError);  // no creature: neither a parameter nor a namespace
}

// Issue 23: the attitude comes from the IMU unless ~attitude_source is tf; ~altitude (m) is
// unset (climb) or finite. A misspelt source or a NaN altitude is refused by its key.
TEST(AnnControllerParams, AttitudeSourceAndAltitudeAreReadOrRefusedByName) {
  const XmlRpc::XmlRpcValue w("w");
  AnnControllerParams p = parseAnnControllerParams(yamlish({{"weights", w}}), "afc");
  EXPECT_EQ(p.attitude_source, AttitudeSource::kImu);
  EXPECT_FALSE(p.altitude.has_value());
  p = parseAnnControllerParams(yamlish({{"weights", w},
                                        {"attitude_source", XmlRpc::XmlRpcValue("tf")},
                                        {"altitude", XmlRpc::XmlRpcValue(4.0)}}),
                               "afc");
  EXPECT_EQ(p.attitude_source, AttitudeSource::kTf);
  ASSERT_TRUE(p.altitude.has_value());
  EXPECT_EQ(*p.altitude, 4.0);
  auto refusal = [&](const char* key, const XmlRpc::XmlRpcValue& value) {
    try {
      parseAnnControllerParams(yamlish({{"weights", w}, {key, value}}), "afc");
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string source = refusal("attitude_source", XmlRpc::XmlRpcValue("gps"));
  EXPECT_NE(source.find("attitude_source"), std::string::npos) << source;
  EXPECT_NE(source.find("'gps' is neither imu nor tf"), std::string::npos) << source;
  const std::string nan = refusal("altitude", XmlRpc::XmlRpcValue(std::nan("")));
  EXPECT_NE(nan.find("altitude"), std::string::npos) << nan;
  EXPECT_NE(nan.find("must be finite"), std::string::npos) << nan;
  // The ground-speed sensor's noise (m/s per axis): 0 unless given, refused below 0 by name.
  EXPECT_EQ(p.velocity_noise, 0.0);
  p = parseAnnControllerParams(
      yamlish({{"weights", w}, {"velocity_noise", XmlRpc::XmlRpcValue(0.05)}}), "afc");
  EXPECT_EQ(p.velocity_noise, 0.05);
  const std::string negative = refusal("velocity_noise", XmlRpc::XmlRpcValue(-0.1));
  EXPECT_NE(negative.find("velocity_noise"), std::string::npos) << negative;
  EXPECT_NE(negative.find("must be in [0, 1000]"), std::string::npos) << negative;
}

// ~altitude asks a network without an altitude input (the paper's, as config/afc_1_weights.yaml)
// to hold a height it cannot (it would climb, its log saying "holding"), and ~attitude_source tf
// gives a network that reads the gyro (the extended one, as config/afc_1_altitude_weights.yaml)
// no rates, and tf gives a network that reads the climb rate no velocity: each refused, naming
// the parameter and the file; the matching pairs pass.
TEST(AnnControllerParams, AParameterTheWeightsFileCannotHonourIsRefusedByName) {
  const flapsim::FlapControllerParams paper;  // neither rate nor altitude inputs
  flapsim::FlapControllerParams extended;
  extended.rate_inputs = extended.altitude_input = true;
  auto mismatch = [](const flapsim::FlapControllerParams& network, const char* key,
                     const XmlRpc::XmlRpcValue& value) {
    const AnnControllerParams p = parseAnnControllerParams(
        yamlish({{"weights", XmlRpc::XmlRpcValue("w.yaml")}, {key, value}}), "afc");
    return annControllerMismatch(p, network, "/afc/ann_controller/attitude_source",
                                 "/afc/ann_controller/altitude");
  };
  EXPECT_EQ(mismatch(paper, "altitude", XmlRpc::XmlRpcValue(4.0)),
            "parameter '/afc/ann_controller/altitude': the network of w.yaml has no altitude "
            "input and cannot hold a height (it climbs): leave it unset, or fly one that has "
            "(config/afc_1_altitude_weights.yaml, config/afc_12_altitude_weights.yaml)");
  EXPECT_EQ(mismatch(extended, "altitude", XmlRpc::XmlRpcValue(4.0)), "");
  EXPECT_EQ(mismatch(extended, "attitude_source", XmlRpc::XmlRpcValue("tf")),
            "parameter '/afc/ann_controller/attitude_source': tf has no angular velocities, and "
            "the network of w.yaml takes the gyro's rates: use imu");
  EXPECT_EQ(mismatch(paper, "attitude_source", XmlRpc::XmlRpcValue("tf")), "");
  flapsim::FlapControllerParams climbing;  // the climb input alone, no gyro
  climbing.climb_input = true;
  EXPECT_EQ(mismatch(climbing, "attitude_source", XmlRpc::XmlRpcValue("tf")),
            "parameter '/afc/ann_controller/attitude_source': tf gives no velocity, and the "
            "network of w.yaml takes the climb rate (odom's twist): use imu");
}

// A flock in one lockstep: lockstep_creatures, a list of non-empty names, with lockstep
// only; the simulator's step size is read from it unless ~step_size is given (0: unset).
TEST(AnnControllerParams, LockstepCreaturesAndStepSize) {
  XmlRpc::XmlRpcValue names;
  names[0] = "afc0";
  names[1] = "afc1";
  const XmlRpc::XmlRpcValue on(true);
  AnnControllerParams p = parseAnnControllerParams(
      yamlish(
          {{"weights", XmlRpc::XmlRpcValue("w")}, {"lockstep", on}, {"lockstep_creatures", names}}),
      "afc");
  EXPECT_EQ(p.lockstep_creatures, (std::vector<std::string>{"afc0", "afc1"}));
  EXPECT_EQ(p.step_size, 0.0);
  // Without lockstep the node would fly ~creature alone: refused, not ignored.
  try {
    parseAnnControllerParams(
        yamlish({{"weights", XmlRpc::XmlRpcValue("w")}, {"lockstep_creatures", names}}), "afc");
    ADD_FAILURE() << "lockstep_creatures was taken without lockstep";
  } catch (const ParamError& e) {
    EXPECT_NE(
        std::string(e.what()).find("'lockstep_creatures': is set, but 'lockstep' is not true"),
        std::string::npos)
        << e.what();
  }
  names[1] = "";
  try {
    parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w")},
                                      {"lockstep", on},
                                      {"lockstep_creatures", names}}),
                             "afc");
    ADD_FAILURE() << "an empty name was taken";
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("lockstep_creatures[1]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w")},
                                                 {"lockstep", on},
                                                 {"lockstep_creatures", XmlRpc::XmlRpcValue(3)}}),
                                        "afc"),
               ParamError);
  EXPECT_THROW(parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w")},
                                                 {"step_size", XmlRpc::XmlRpcValue(0.0)}}),
                                        "afc"),
               ParamError);
  p = parseAnnControllerParams(
      yamlish({{"weights", XmlRpc::XmlRpcValue("w")}, {"step_size", XmlRpc::XmlRpcValue(5e-4)}}),
      "afc");
  EXPECT_EQ(p.step_size, 5e-4);
}

TEST(AnnControllerParams, MessageNamesTheUnitWings) {
  const flapsim::FlapUnitLayout layout = flapsim::flapUnitLayout(2);
  std::vector<flapsim::StrokeCommand> strokes(4, flapsim::StrokeCommand{30, 10, 1.2});
  strokes[3].downstroke_rate = 55;
  const flapsim::WingCommand msg = annCommandMsg(layout, strokes);
  ASSERT_EQ(msg.joint_names.size(), 4u);
  EXPECT_EQ(msg.joint_names[3], "unit1_wing_right_joint");
  EXPECT_EQ(msg.downstroke_rate[3], 55.0);
  EXPECT_EQ(msg.amplitude[0], 1.2);
}

// The controllers read their namespace with the simulator's reader: a misspelt key is refused
// by name, as the weights and gains files refuse theirs (it used to be warned and the default
// flown), and a wrong type names its key.
TEST(ControllerParams, MisspeltKeysAreRefusedByNameAndTypesChecked) {
  auto refusal = [](auto parse) {
    try {
      parse();
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal([] {
              parseStrokeControllerParams(yamlish({{"amplitud", XmlRpc::XmlRpcValue(0.5)},
                                                   {"rate", XmlRpc::XmlRpcValue(20)}}),
                                          "c");
            }),
            "parameter 'amplitud': unknown parameter (misspelt?)");
  EXPECT_EQ(refusal([] {
              parseAnnControllerParams(yamlish({{"weights", XmlRpc::XmlRpcValue("w.yaml")},
                                                {"lock_step", XmlRpc::XmlRpcValue(true)}}),
                                       "c");
            }),
            "parameter 'lock_step': unknown parameter (misspelt?)");
  EXPECT_EQ(
      refusal([] {
        parseHoverControllerParams(yamlish({{"heigth_gain", XmlRpc::XmlRpcValue(3.0)}}), "hover");
      }),
      "parameter 'heigth_gain': unknown parameter (misspelt?)");
  const std::string typed = refusal([] {
    parseAnnControllerParams(
        yamlish({{"weights", XmlRpc::XmlRpcValue("w.yaml")}, {"lockstep", XmlRpc::XmlRpcValue(1)}}),
        "c");
  });
  EXPECT_NE(typed.find("'lockstep': must be true or false"), std::string::npos) << typed;
}

// ann_controller's ~rate is bounded as the weights file's control period is ([0.001, 10] s):
// 1e-9 Hz never commanded the creature, 1e9 Hz flooded it; 0 takes the file's period.
TEST(ControllerParams, AnnRateIsBoundedAsTheControlPeriod) {
  auto rate = [](double hz) {
    return yamlish({{"weights", XmlRpc::XmlRpcValue("w.yaml")}, {"rate", XmlRpc::XmlRpcValue(hz)}});
  };
  for (double hz : {0.0, 0.1, 50.0, 1000.0}) {
    EXPECT_EQ(parseAnnControllerParams(rate(hz), "c").rate, hz);
  }
  for (double hz : {1e-9, 0.0999, 1000.1, 1e9, -50.0}) {
    try {
      parseAnnControllerParams(rate(hz), "c");
      ADD_FAILURE() << hz << " Hz accepted";
    } catch (const ParamError& e) {
      EXPECT_NE(std::string(e.what()).find("'rate': must be 0 (the weights file's control period) "
                                           "or in [0.1, 1000] Hz"),
                std::string::npos)
          << e.what();
    }
  }
}

// hover_controller reads ~gains_file with the reader flight_check --gains uses: the same file
// gives the same gains, a key given twice or misspelt in it is refused naming the file and the
// key, and a gain given as a parameter overrides the file's.
TEST(HoverControllerParams, AGainsFileIsReadAsFlightCheckReadsIt) {
  flapsim::HoverControllerParams written;
  for (const flapsim::HoverParamField& f : flapsim::hoverParamFields()) {
    written.*f.member *= 1.25;  // not the defaults
  }
  const std::string path = ::testing::TempDir() + "hover_gains.yaml";
  std::ofstream(path) << flapsim::hoverGainsToYaml(written, "test gains", {});
  const flapsim::HoverControllerParams file = flapsim::loadHoverGainsYaml(path);
  const HoverControllerNodeParams p = parseHoverControllerParams(
      yamlish({{"gains_file", XmlRpc::XmlRpcValue(path)}, {"altitude", XmlRpc::XmlRpcValue(4.5)}}),
      "hover");
  for (const flapsim::HoverParamField& f : flapsim::hoverParamFields()) {
    if (std::string(f.name) == "altitude") continue;
    EXPECT_EQ(p.controller.*f.member, file.*f.member) << f.name;
    EXPECT_EQ(p.controller.*f.member, written.*f.member) << f.name;
  }
  EXPECT_EQ(p.controller.altitude, 4.5);
  const std::string twice = ::testing::TempDir() + "twice_gains.yaml";
  std::ofstream(twice) << "roll_gain: 1\nroll_gain: 2\n";
  try {
    parseHoverControllerParams(yamlish({{"gains_file", XmlRpc::XmlRpcValue(twice)}}), "hover");
    ADD_FAILURE() << "a key given twice was read";
  } catch (const ParamError& e) {
    EXPECT_EQ(std::string(e.what()),
              "parameter 'gains_file': " + twice + ": key 'roll_gain' given twice");
  }
}

// Both controllers build their message with the one WingCommand builder: a feather angle is
// kept (in the message only if some wing has one), and reads back as it was sent.
TEST(ControllerMessages, KeepTheFeatherAngle) {
  std::vector<flapsim::StrokeCommand> strokes(2, flapsim::StrokeCommand{30, 10, 1.2});
  strokes[1].feather = 0.4;
  const flapsim::WingCommand ann = annCommandMsg(flapsim::flapUnitLayout(1), strokes);
  EXPECT_EQ(ann.feather_angle, (std::vector<double>{0.0, 0.4}));
  EXPECT_EQ(fromMsg(ann).strokes[1].feather, 0.4);
  const flapsim::WingCommand stroke = strokeCommandMsg({strokes[1]});  // one pair: both wings
  EXPECT_EQ(stroke.feather_angle, (std::vector<double>{0.4, 0.4}));
  EXPECT_TRUE(strokeCommandMsg({strokes[0]}).feather_angle.empty());
}

// The message of the ParamError `f` throws ("" if none).
template <typename F>
std::string paramRefusal(F f) {
  try {
    f();
  } catch (const ParamError& e) {
    return e.what();
  }
  return "";
}

TEST(AnnControllerParams, GyroBiasIsThreeFiniteNumbersAndRefusedWithTf) {
  const XmlRpc::XmlRpcValue w("w");
  EXPECT_EQ(parseAnnControllerParams(yamlish({{"weights", w}}), "afc").gyro_bias,
            flapsim::Vec3::Zero());
  EXPECT_EQ(parseAnnControllerParams(
                yamlish({{"weights", w}, {"gyro_bias", list({0.01, -0.002, 0.003})}}), "afc")
                .gyro_bias,
            flapsim::Vec3(0.01, -0.002, 0.003));
  for (const XmlRpc::XmlRpcValue& bad : {list({0.01, 0.02}), list({0.0, std::nan(""), 0.0}),
                                         list({0.0, 0.0, 2e3}), XmlRpc::XmlRpcValue(0.02)}) {
    const std::string why = paramRefusal([&] {
      parseAnnControllerParams(yamlish({{"weights", w}, {"gyro_bias", bad}}), "afc");
    });
    EXPECT_NE(why.find("parameter 'gyro_bias"), std::string::npos) << why;  // [i]: the item
  }
  const std::string tf = paramRefusal([&] {
    parseAnnControllerParams(yamlish({{"weights", w},
                                      {"attitude_source", XmlRpc::XmlRpcValue("tf")},
                                      {"gyro_bias", list({0.01, 0.0, 0.0})}}),
                             "afc");
  });
  EXPECT_NE(tf.find("'gyro_bias': is set, but tf"), std::string::npos) << tf;
}

TEST(DisturbanceParams, DefaultsAreFlightChecksAndGivenSizesAreTaken) {
  const DisturbanceParams d = parseDisturbanceParams(XmlRpc::XmlRpcValue(), "afc");
  EXPECT_EQ(d.creature, "afc");
  EXPECT_EQ(d.draw.seed, flapsim::FlightCheckParams().seed);
  EXPECT_EQ(d.draw.duration, flapsim::FlightCheckParams().duration);
  EXPECT_FALSE(d.draw.torque.has_value());
  EXPECT_FALSE(d.draw.force.has_value());
  EXPECT_EQ(d.apply_wrench_service, "/flapsim/apply_wrench");
  const DisturbanceParams p =
      parseDisturbanceParams(yamlish({{"creature", XmlRpc::XmlRpcValue("afc3")},
                                      {"seed", XmlRpc::XmlRpcValue(7)},
                                      {"duration", XmlRpc::XmlRpcValue(30.0)},
                                      {"torque", XmlRpc::XmlRpcValue(0.05)},
                                      {"push", XmlRpc::XmlRpcValue(0)}}),
                             "ignored");
  EXPECT_EQ(p.creature, "afc3");
  EXPECT_EQ(p.draw.seed, 7u);
  EXPECT_EQ(p.draw.duration, 30.0);
  EXPECT_EQ(p.draw.torque, 0.05);
  EXPECT_EQ(p.draw.force, 0.0);
}

TEST(DisturbanceParams, BadValuesAreRefusedByName) {
  const std::pair<const char*, XmlRpc::XmlRpcValue> bad[] = {
      {"seed", XmlRpc::XmlRpcValue(-1)},          {"seed", XmlRpc::XmlRpcValue(1.5)},
      {"duration", XmlRpc::XmlRpcValue(0.0)},     {"duration", XmlRpc::XmlRpcValue(std::nan(""))},
      {"torque", XmlRpc::XmlRpcValue(-0.01)},     {"torque", XmlRpc::XmlRpcValue(std::nan(""))},
      {"push", XmlRpc::XmlRpcValue(-1.0)},        {"push", XmlRpc::XmlRpcValue("strong")},
      {"wait_timeout", XmlRpc::XmlRpcValue(0.0)}, {"creature", XmlRpc::XmlRpcValue("a b")},
      {"torqe", XmlRpc::XmlRpcValue(0.1)}};
  for (const auto& [key, value] : bad) {
    const std::string why = paramRefusal([&] {
      parseDisturbanceParams(yamlish({{key, value}}), "afc");
    });
    EXPECT_NE(why.find("'" + std::string(key) + "'"), std::string::npos) << key << ": " << why;
  }
}

TEST(NamespaceBasename, LastComponent) {
  EXPECT_EQ(namespaceBasename("/flock/afc3"), "afc3");
  EXPECT_EQ(namespaceBasename("/afc/"), "afc");
  EXPECT_EQ(namespaceBasename("/"), "");
}

// hover_controller reads the lockstep keys as ann_controller does: free running by default,
// lockstep with its duration and step size when set; a step size <= 0 is refused by name.
TEST(HoverControllerParams, LockstepKeysAsAnnController) {
  const HoverControllerNodeParams d = parseHoverControllerParams(XmlRpc::XmlRpcValue(), "hover");
  EXPECT_EQ(d.creature, "hover");
  EXPECT_FALSE(d.lockstep);
  EXPECT_EQ(d.step_size, 0.0);
  EXPECT_EQ(d.rate, 100.0);
  const HoverControllerNodeParams p =
      parseHoverControllerParams(yamlish({{"lockstep", XmlRpc::XmlRpcValue(true)},
                                          {"lockstep_duration", XmlRpc::XmlRpcValue(60.0)},
                                          {"step_size", XmlRpc::XmlRpcValue(0.0005)},
                                          {"altitude", XmlRpc::XmlRpcValue(2.5)}}),
                                 "hover");
  EXPECT_TRUE(p.lockstep);
  EXPECT_EQ(p.lockstep_duration, 60.0);
  EXPECT_EQ(p.step_size, 0.0005);
  EXPECT_EQ(p.step_service, "/flapsim/step");
  EXPECT_EQ(p.controller.altitude, 2.5);
  try {
    parseHoverControllerParams(yamlish({{"step_size", XmlRpc::XmlRpcValue(0.0)}}), "hover");
    ADD_FAILURE() << "step_size 0 was taken";
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("step_size"), std::string::npos) << e.what();
  }
}

// Every field of the gains file (flapsim/hover_gains.h, loaded by hover.launch as the node's
// private parameters) is a parameter of the node, none left at its default.
TEST(HoverControllerParams, EveryGainOfTheGainsFileIsAParameter) {
  XmlRpc::XmlRpcValue ns;
  ns.begin();
  const flapsim::HoverControllerParams hand;
  for (const flapsim::HoverParamField& f : flapsim::hoverParamFields()) {
    ns[f.name] = XmlRpc::XmlRpcValue(1.5 * (hand.*f.member));
  }
  const HoverControllerNodeParams p = parseHoverControllerParams(ns, "hover");
  for (const flapsim::HoverParamField& f : flapsim::hoverParamFields()) {
    EXPECT_EQ(p.controller.*f.member, 1.5 * (hand.*f.member)) << f.name;
  }
  ns["max_roll_share"] = XmlRpc::XmlRpcValue(1.5);
  try {
    parseHoverControllerParams(ns, "hover");
    ADD_FAILURE() << "max_roll_share 1.5 was taken";
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("max_roll_share must be in [0, 1)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace flapsim_ros
