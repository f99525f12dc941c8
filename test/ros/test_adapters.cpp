// Adapters of the simulator node, without a master: parameters -> structs
// (including every kind of bad parameter) and structs <-> messages.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <string>

#include "flapsim/creature_model.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/creature_publishers.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/request_names.h"
#include "flapsim_ros/tf_publisher.h"
#include "yaml_params.h"

namespace {

using flapsim::Vec3;
using flapsim_ros::ParamError;
using flapsim_test::toXmlRpc;
using XmlRpc::XmlRpcValue;

std::string sourcePath(const std::string& relative) {
  return std::string(FLAPSIM_SOURCE_DIR) + "/" + relative;
}

XmlRpcValue yaml(const std::string& text) { return toXmlRpc(YAML::Load(text)); }

// The message of the ParamError thrown by parsing `text`; "" if none.
std::string paramError(const std::string& text) {
  try {
    flapsim_ros::parseNodeParams(yaml(text));
  } catch (const ParamError& e) {
    return e.what();
  }
  return "";
}

const char* kCreature = "creatures: [{name: a, urdf_file: /x.urdf";

// ---- parameters ------------------------------------------------------------------------

TEST(Params, NothingSetGivesTheDefaults) {
  flapsim_ros::NodeParams p = flapsim_ros::parseNodeParams(XmlRpcValue());
  EXPECT_EQ(p.world.step_size, 0.001);
  EXPECT_EQ(p.publish_rate, 100.0);
  EXPECT_EQ(p.real_time_factor, 1.0);
  EXPECT_FALSE(p.paused);
  EXPECT_EQ(p.world_frame, "world");
  EXPECT_EQ(p.world.air.density, 1.204);
  EXPECT_TRUE(p.markers.enabled);
  EXPECT_TRUE(p.creatures.empty());
}

TEST(Params, ShippedConfigParsesToItsNumbers) {
  flapsim_ros::NodeParams p =
      flapsim_ros::parseNodeParams(toXmlRpc(YAML::LoadFile(sourcePath("config/flapsim.yaml"))));
  EXPECT_TRUE(p.unknown_keys.empty());
  EXPECT_EQ(p.world.step_size, 0.001);
  EXPECT_EQ(p.publish_rate, 100.0);
  EXPECT_EQ(p.world.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(p.world.air.drag_coefficient, 1.15);
  EXPECT_EQ(p.world.air.subdivisions_u, 4);
  EXPECT_EQ(p.world.air.subdivisions_v, 4);
  EXPECT_EQ(p.markers.scale, 2.0);
  EXPECT_FALSE(p.markers.per_cell);
  EXPECT_EQ(p.world.air.turbulence.wind_at_6m, 0.0);
  EXPECT_EQ(p.world.air.turbulence.height, 5.0);
  EXPECT_EQ(p.world.air.gust.velocity, Vec3::Zero());
}

TEST(Params, OverridesReachTheStructs) {
  flapsim_ros::NodeParams p = flapsim_ros::parseNodeParams(yaml(R"(
step_size: 0.002
publish_rate: 50            # an integer where a number is expected
real_time_factor: 0
paused: true
world_frame: map
ground: false
threads: 2
air: {density: 1000, wind: [1, 2.5, -3], subdivisions: [2, 3], buoyancy: false,
      added_mass_products: kirchhoff, rotational_lift: false, centre_of_pressure_shift: false,
      model: quasi_steady, quasi_steady: {lift_mean: 0.3, drag_phase: -9}}
markers: {scale: 0.1, per_cell: true}
something_else: 1
creatures:
  - name: plate_a
    urdf_file: /tmp/plate.urdf
    pose: {xyz: [1, 2, 3], rpy: [0, 0, 1.5707963267948966]}
    twist: {linear: [0, 0, 1], angular: [0, 0, 150]}
  - name: b
    urdf_param: /robot_description
    wing_command: {downstroke_rate: 40, upstroke_rate: 10, amplitude: 0.8}
  - name: c
    urdf_xml: "<robot name='c'/>"
    wing_command: {downstroke_rate: [30, 31], upstroke_rate: [10, 11], amplitude: [0.8, 0.7],
                   feather: [1.2, 1.1]}
)"));
  EXPECT_EQ(p.world.step_size, 0.002);
  EXPECT_EQ(p.publish_rate, 50.0);
  EXPECT_EQ(p.real_time_factor, 0.0);
  EXPECT_TRUE(p.paused);
  EXPECT_EQ(p.world_frame, "map");
  EXPECT_FALSE(p.world.ground);
  EXPECT_EQ(p.world.air.density, 1000.0);
  EXPECT_EQ(p.world.air.wind, Vec3(1, 2.5, -3));
  EXPECT_EQ(p.world.air.subdivisions_u, 2);
  EXPECT_EQ(p.world.air.subdivisions_v, 3);
  EXPECT_FALSE(p.world.air.buoyancy);
  EXPECT_EQ(p.world.air.added_mass_products, flapsim::AddedMassProducts::kKirchhoff);
  EXPECT_FALSE(p.world.air.rotational_lift);  // both true by default
  EXPECT_FALSE(p.world.air.centre_of_pressure_shift);
  EXPECT_EQ(p.world.threads, 2);
  EXPECT_EQ(p.world.air.model, "quasi_steady");
  EXPECT_EQ(p.world.air.quasi_steady.lift_mean, 0.3);
  EXPECT_EQ(p.world.air.quasi_steady.drag_phase, -9.0);
  EXPECT_EQ(p.world.air.quasi_steady.lift_amplitude, 1.58);  // untouched default
  EXPECT_EQ(p.markers.scale, 0.1);
  EXPECT_TRUE(p.markers.per_cell);
  ASSERT_EQ(p.unknown_keys, std::vector<std::string>{"something_else"});
  ASSERT_EQ(p.creatures.size(), 3u);
  const auto& a = p.creatures[0];
  EXPECT_EQ(a.name, "plate_a");
  EXPECT_EQ(a.urdf_file, "/tmp/plate.urdf");
  EXPECT_EQ(a.pose.position, Vec3(1, 2, 3));
  // yaw pi/2 about z: q = (cos(pi/4), 0, 0, sin(pi/4))
  EXPECT_NEAR(a.pose.orientation.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a.pose.orientation.z(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a.pose.orientation.x(), 0.0, 1e-15);
  EXPECT_EQ(a.twist.linear, Vec3(0, 0, 1));
  EXPECT_EQ(a.twist.angular, Vec3(0, 0, 150));
  EXPECT_TRUE(a.wing_command.empty());
  EXPECT_EQ(p.creatures[1].urdf_param, "/robot_description");
  ASSERT_EQ(p.creatures[1].wing_command.size(), 1u);
  EXPECT_EQ(p.creatures[1].wing_command[0].downstroke_rate, 40.0);
  EXPECT_EQ(p.creatures[1].wing_command[0].upstroke_rate, 10.0);
  EXPECT_EQ(p.creatures[1].wing_command[0].amplitude, 0.8);
  EXPECT_EQ(p.creatures[2].urdf_xml, "<robot name='c'/>");
  ASSERT_EQ(p.creatures[2].wing_command.size(), 2u);
  EXPECT_EQ(p.creatures[2].wing_command[1].downstroke_rate, 31.0);
  EXPECT_EQ(p.creatures[2].wing_command[1].amplitude, 0.7);
  EXPECT_EQ(p.creatures[2].wing_command[1].feather, 1.1);
  EXPECT_EQ(p.creatures[1].wing_command[0].feather, 0.0);
}

// A turbulence level sets the wind at 6 m (15, 30, 45 kt), frozen Taylor's field, and the gust
// its shape.
TEST(Params, TurbulenceAndGustReachTheAir) {
  const flapsim_ros::NodeParams p = flapsim_ros::parseNodeParams(yaml(R"(
air: {turbulence: {level: moderate, height: 10, per_creature: true, frozen: true, seed: 7},
      gust: {velocity: [0, 2, 0.5], start: 3, rise: 0.4, hold: 1}}
)"));
  const flapsim::TurbulenceParams& t = p.world.air.turbulence;
  EXPECT_DOUBLE_EQ(t.wind_at_6m, 30.0 * 1852.0 / 3600.0);
  EXPECT_EQ(t.height, 10.0);
  EXPECT_TRUE(t.per_creature);
  EXPECT_TRUE(t.frozen);
  EXPECT_EQ(t.seed, 7u);
  const flapsim::DiscreteGust& g = p.world.air.gust;
  EXPECT_EQ(g.velocity, Vec3(0, 2, 0.5));
  EXPECT_EQ(g.start, 3.0);
  EXPECT_EQ(g.rise, 0.4);
  EXPECT_EQ(g.hold, 1.0);
  EXPECT_EQ(flapsim_ros::parseNodeParams(yaml("air: {turbulence: {wind_at_6m: 4.5}}"))
                .world.air.turbulence.wind_at_6m,
            4.5);
  EXPECT_EQ(flapsim_ros::parseNodeParams(yaml("air: {turbulence: {level: none}}"))
                .world.air.turbulence.wind_at_6m,
            0.0);
}

TEST(Params, BadParametersAreNamed) {
  struct Case {
    std::string yaml, expect;
  };
  const std::string c = kCreature;
  const Case cases[] = {
      {"publish_rate: -1", "'publish_rate'"},
      {"publish_rate: 0", "'publish_rate'"},
      {"real_time_factor: fast", "'real_time_factor': must be a number"},
      {"real_time_factor: -0.5", "'real_time_factor'"},
      {"paused: 1", "'paused': must be true or false"},
      {"step_size: 0", "step_size"},
      {"step_size: .nan", "'step_size': must be finite"},
      {"gravity: [0, 0]", "'gravity': must have 3 numbers"},
      {"gravity: [0, 0, x]", "'gravity[2]'"},
      {"solver_iterations: 2.5", "'solver_iterations': must be an integer"},
      {"air: {desnity: 1.2}", "'air/desnity': unknown parameter"},
      {"air: {density: -1}", "air density"},
      {"air: {subdivisions: [4]}", "'air/subdivisions'"},
      {"air: {subdivisions: [4, 2.5]}", "'air/subdivisions'"},
      {"air: 3", "'air': must be a dictionary"},
      {"air: {model: cfd}", "'air/model': unknown air model 'cfd'"},
      {"air: {added_mass_products: full}",
       "'air/added_mass_products': unknown added-mass products 'full' (omitted, kirchhoff, shed)"},
      {"air: {added_mass_shed_products: true}",
       "'air/added_mass_shed_products': replaced by air/added_mass_products"},
      {"air: {quasi_steady: {lift_man: 1}}", "'air/quasi_steady/lift_man': unknown"},
      {"air: {turbulence: {level: stormy}}", "'air/turbulence/level': turbulence level 'stormy'"},
      {"air: {turbulence: {level: light, wind_at_6m: 3}}", "'air/turbulence/level': give a level"},
      {"air: {turbulence: {level: light, height: 1}}", "air/turbulence/height must be in [3.048"},
      {"air: {turbulence: {wind_at_6m: -1}}", "air/turbulence/wind_at_6m must be in [0, 100]"},
      {"air: {turbulence: {seed: -2}}", "'air/turbulence/seed': must be >= 0"},
      {"air: {turbulence: {levle: light}}", "'air/turbulence/levle': unknown"},
      {"air: {gust: {velocity: [0, 1, 0], rise: 0}}", "air/gust/rise must be in (0, 1e6]"},
      {"air: {gust: {velocity: [0, 1]}}", "'air/gust/velocity': must have 3 numbers"},
      {"air: {gust: {velocity: [0, 1, 0], start: -1}}", "air/gust/start must be >= 0"},
      {"threads: 0", "threads must be in 1..256"},
      {"markers: {width: 0}", "'markers/width'"},
      {"imu: {angular_velocity_noise: -0.1}", "'imu/angular_velocity_noise': must be in"},
      {"imu: {linear_acceleration_noise: .nan}", "'imu/linear_acceleration_noise'"},
      {"imu: {seed: 1.5}", "'imu/seed': must be an integer"},
      {"imu: {noise: 1}", "'imu/noise': unknown parameter"},
      {"markers: {scale: -1}", "'markers/scale'"},
      {"world_frame: ''", "'world_frame'"},
      {"creatures: {name: a}", "'creatures': must be a list"},
      {"creatures: [{urdf_file: /x.urdf}]", "'creatures[0]/name': missing"},
      {"creatures: [{name: 'a b', urdf_file: /x.urdf}]",
       "'creatures[0]/name': creature name 'a b'"},
      {"creatures: [{name: 9a, urdf_file: /x.urdf}]", "must start with a letter"},
      {"creatures: [{name: a}]", "creature 'a' needs exactly one of"},
      {"creatures: [{name: a, urdf_file: /x.urdf, urdf_xml: '<robot/>'}]", "needs exactly one"},
      {c + "}, {name: a, urdf_file: /y.urdf}]", "'creatures[1]/name': creature name 'a' is taken"},
      {c + ", pose: {xyz: [1, 2]}}]", "'creatures[0]/pose/xyz': must have 3 numbers"},
      {c + ", pose: {xyz: [1, 2, 3], ryp: [0, 0, 0]}}]", "'creatures[0]/pose/ryp': unknown"},
      {c + ", twist: {angular: [0, 0, .inf]}}]", "'creatures[0]/twist/angular[2]': must be finite"},
      {c + ", colour: red}]", "'creatures[0]/colour': unknown"},
      {c + ", wing_command: {downstroke_rate: -1, upstroke_rate: 10, amplitude: 0.8}}]",
       "'creatures[0]/wing_command': downstroke rate must be finite and >= 0"},
      {c + ", wing_command: {downstroke_rate: [1, 2], upstroke_rate: [1], amplitude: [1, 1]}}]",
       "'creatures[0]/wing_command': needs downstroke_rate, upstroke_rate and amplitude of equal"},
      {c + ", wing_command: {downstroke_rate: 1, upstroke_rate: 1}}]",
       "'creatures[0]/wing_command/amplitude': missing"},
      {c + ", wing_command: {downstroke_rate: 1, upstroke_rate: 1, amplitude: 1, feather: 2}}]",
       "'creatures[0]/wing_command': feather angle must be finite and within +-pi/2"},
      {c + ", wing_command: {downstroke_rate: 1, upstroke_rate: 1, amplitude: 1, feather: [1, "
           "1]}}]",
       "'creatures[0]/wing_command/feather': must have as many entries"},
  };
  for (const Case& k : cases) {
    const std::string msg = paramError(k.yaml);
    EXPECT_NE(msg.find(k.expect), std::string::npos)
        << "yaml: " << k.yaml << "\nerror: '" << msg << "'\nexpected to contain: " << k.expect;
  }
}

// Values that were accepted and then froze the node (a step of 1 ns, a publication every
// 1e7 s, a real-time factor of 1e-9 that made SIGINT wait) or made NaN (wind 1e300).
TEST(Params, StartUpRangesAreNamed) {
  struct Case {
    std::string yaml, expect;
  };
  const Case cases[] = {
      {"step_size: 1.0e-9", "bad world parameters: step_size must be in [1e-6, 0.1] s"},
      {"publish_rate: 1.0e-7", "parameter 'publish_rate': must be in [0.01, 1e6] Hz"},
      {"publish_rate: 1.0e-300", "parameter 'publish_rate': must be in [0.01, 1e6] Hz"},
      {"real_time_factor: 1.0e-9",
       "parameter 'real_time_factor': must be 0 (as fast as possible) or in [0.001, 1e6]"},
      {"max_steps_per_call: 0", "parameter 'max_steps_per_call': must be >= 1"},
      {"max_speed: -1", "bad world parameters: max_speed must be in (0, 3e8] m/s"},
      {"max_cells: 0", "bad world parameters: max_cells must be >= 1"},
      {"air: {wind: [1.0e+300, 0, 0]}",
       "bad world parameters: air wind must be finite, each component within +-1000 m/s"},
      {"urdf_roots: []", "parameter 'urdf_roots': must list at least one directory"},
      {"urdf_roots: [1]", "parameter 'urdf_roots[0]': must be a string, got an integer"},
      {"wing_command_timeout: -1", "parameter 'wing_command_timeout': must be in [0, 1e6] s"},
      {"wing_command_timeout_action: stop",
       "parameter 'wing_command_timeout_action': must be 'hold' or 'release', got 'stop'"},
      {"controller_wait_timeout: -1", "parameter 'controller_wait_timeout': must be in [0, 1e6] s"},
      {"view: {distance: 0}", "parameter 'view/distance': must be in (0, 1e4] m"},
      {"view: {pitch: 1.6}", "parameter 'view/pitch': must be within +-pi/2 (exclusive)"},
      {"view: {zoom: 1}", "parameter 'view/zoom': unknown parameter (misspelt?)"},
  };
  for (const Case& k : cases) {
    EXPECT_EQ(paramError(k.yaml), k.expect) << k.yaml;
  }
  const flapsim_ros::NodeParams p = flapsim_ros::parseNodeParams(
      yaml("{max_speed: 50, max_cells: 1000, max_steps_per_call: 7, urdf_roots: [/a, /b]}"));
  EXPECT_EQ(p.world.max_speed, 50.0);
  EXPECT_EQ(p.world.max_cells, 1000);
  EXPECT_EQ(p.max_steps_per_call, 7);
  EXPECT_EQ(p.urdf_roots, (std::vector<std::string>{"/a", "/b"}));
  EXPECT_TRUE(flapsim_ros::parseNodeParams(XmlRpcValue()).urdf_roots.empty());
  // a launch argument: one string, ':'-separated; "" keeps the defaults
  EXPECT_EQ(flapsim_ros::parseNodeParams(yaml("{urdf_roots: '/a::/b/c'}")).urdf_roots,
            (std::vector<std::string>{"/a", "/b/c"}));
  EXPECT_TRUE(flapsim_ros::parseNodeParams(yaml("{urdf_roots: ''}")).urdf_roots.empty());
  const flapsim_ros::NodeParams t = flapsim_ros::parseNodeParams(
      yaml("{wing_command_timeout: 0.5, wing_command_timeout_action: release}"));
  EXPECT_EQ(t.wing_command_timeout, 0.5);
  EXPECT_EQ(t.wing_command_timeout_action, flapsim_ros::CommandTimeoutAction::kRelease);
  EXPECT_EQ(flapsim_ros::parseNodeParams(XmlRpcValue()).wing_command_timeout, 0.0);
  // The wait for a creature's controller (its `controller`, a node name for the messages).
  EXPECT_EQ(flapsim_ros::parseNodeParams(XmlRpcValue()).controller_wait_timeout, 30.0);
  const flapsim_ros::NodeParams w = flapsim_ros::parseNodeParams(
      yaml("{controller_wait_timeout: 0, creatures: [{name: a, urdf_file: /x.urdf, controller: "
           "/a/ann_controller}, {name: b, urdf_file: /x.urdf}]}"));
  EXPECT_EQ(w.controller_wait_timeout, 0.0);
  EXPECT_EQ(w.creatures.at(0).controller, "/a/ann_controller");
  EXPECT_EQ(w.creatures.at(1).controller, "");
}

// Request fields under gazebo_msgs' names and the former ones (srv/*.srv): either, or both
// alike; a link field may be "<creature>::<link>".
TEST(RequestNames, EitherNameAndCreatureLinkForms) {
  using flapsim_ros::requestBody;
  const std::string fu = "fu", plate = "plate", none, body = "unit0_body", full = "fu::unit0_body";
  EXPECT_EQ(flapsim_ros::eitherField({"model_name", fu}, {"name", none}), "fu");
  EXPECT_EQ(flapsim_ros::eitherField({"model_name", none}, {"name", fu}), "fu");
  EXPECT_EQ(flapsim_ros::eitherField({"model_name", fu}, {"name", fu}), "fu");
  EXPECT_THROW(flapsim_ros::eitherField({"model_name", fu}, {"name", plate}), flapsim::InputError);
  for (const auto& b : {requestBody({"m", fu}, {"n", none}, {"l", body}, {"o", none}),
                        requestBody({"m", none}, {"n", none}, {"l", full}, {"o", none}),
                        requestBody({"m", none}, {"n", fu}, {"l", none}, {"o", full}),
                        requestBody({"m", fu}, {"n", fu}, {"l", full}, {"o", body})}) {
    EXPECT_EQ(b.creature, "fu");
    EXPECT_EQ(b.link, "unit0_body");
  }
  const std::string plate_body = "plate::unit0_body", wing = "wing";
  EXPECT_THROW(requestBody({"m", none}, {"n", none}, {"l", full}, {"o", plate_body}),
               flapsim::InputError);
  EXPECT_THROW(requestBody({"m", fu}, {"n", none}, {"l", body}, {"o", wing}), flapsim::InputError);
  const std::string odd = "a/b::c";  // not a creature's name before '::': a link name
  EXPECT_EQ(requestBody({"m", fu}, {"n", none}, {"l", odd}, {"o", none}).link, odd);
  try {
    requestBody({"model_name", plate}, {"name", none}, {"body_name", full}, {"link", none});
    ADD_FAILURE() << "a link of another creature was taken";
  } catch (const flapsim::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "body_name 'fu::unit0_body' is a link of 'fu', not of model_name 'plate'");
  }
}

TEST(Params, CreatureNames) {
  EXPECT_EQ(flapsim_ros::validateCreatureName("flap_unit"), "");
  EXPECT_EQ(flapsim_ros::validateCreatureName("Plate10"), "");
  EXPECT_NE(flapsim_ros::validateCreatureName(""), "");
  EXPECT_NE(flapsim_ros::validateCreatureName("_x"), "");
  EXPECT_NE(flapsim_ros::validateCreatureName("a/b"), "");
  EXPECT_NE(flapsim_ros::validateCreatureName("a-b"), "");
  EXPECT_NE(flapsim_ros::validateCreatureName("~a"), "");
}

// ---- conversions -----------------------------------------------------------------------

TEST(Conversions, PoseAndTwistRoundTrip) {
  flapsim::Pose p{Vec3(1.5, -2, 3.25), flapsim::Quat(0.5, 0.5, -0.5, 0.5)};
  geometry_msgs::Pose m = flapsim_ros::toMsg(p);
  EXPECT_EQ(m.position.x, 1.5);
  EXPECT_EQ(m.orientation.w, 0.5);
  EXPECT_EQ(m.orientation.y, -0.5);  // Eigen order: w, x, y, z
  flapsim::Pose q = flapsim_ros::fromMsg(m);
  EXPECT_EQ(q.position, p.position);
  EXPECT_EQ(q.orientation.coeffs(), p.orientation.coeffs());

  geometry_msgs::Pose zero;  // all-zero quaternion: identity
  EXPECT_EQ(flapsim_ros::fromMsg(zero).orientation.coeffs(), flapsim::Quat::Identity().coeffs());

  flapsim::Twist t{Vec3(1, 2, 3), Vec3(-4, 5, -6)};
  flapsim::Twist u = flapsim_ros::fromMsg(flapsim_ros::toMsg(t));
  EXPECT_EQ(u.linear, t.linear);
  EXPECT_EQ(u.angular, t.angular);
}

TEST(Conversions, SimTimeIsExactInSteps) {
  EXPECT_EQ(flapsim_ros::stepNanoseconds(0.001), 1000000u);
  EXPECT_EQ(flapsim_ros::stepNanoseconds(0.0005), 500000u);
  EXPECT_EQ(flapsim_ros::stepNanoseconds(1e-12), 1u);
  ros::Time t = flapsim_ros::simTime(7, 1000000);
  EXPECT_EQ(t.sec, 0u);
  EXPECT_EQ(t.nsec, 7000000u);
  // 10^7 steps of 1 ms = 10^4 s on the nanosecond
  t = flapsim_ros::simTime(10000000, 1000000);
  EXPECT_EQ(t.sec, 10000u);
  EXPECT_EQ(t.nsec, 0u);
}

TEST(Conversions, WingCommandLengthsAreChecked) {
  flapsim::WingCommand m;
  m.downstroke_rate = {30, 40};
  m.upstroke_rate = {10, 11};
  m.amplitude = {0.8, 0.7};
  flapsim_ros::WingCommandRequest r = flapsim_ros::fromMsg(m);
  EXPECT_TRUE(r.joints.empty());
  ASSERT_EQ(r.strokes.size(), 2u);
  EXPECT_EQ(r.strokes[1].downstroke_rate, 40.0);
  EXPECT_EQ(r.strokes[1].upstroke_rate, 11.0);
  EXPECT_EQ(r.strokes[1].amplitude, 0.7);
  flapsim::WingCommand back = flapsim_ros::toMsg(r);
  EXPECT_EQ(back.downstroke_rate, m.downstroke_rate);
  EXPECT_EQ(back.amplitude, m.amplitude);
  EXPECT_TRUE(back.feather_angle.empty());  // no feathering: the optional array stays empty
  EXPECT_EQ(r.strokes[0].feather, 0.0);

  flapsim::WingCommand feathered = m;
  feathered.feather_angle = {1.2, 0.0};
  r = flapsim_ros::fromMsg(feathered);
  EXPECT_EQ(r.strokes[0].feather, 1.2);
  EXPECT_EQ(flapsim_ros::toMsg(r).feather_angle, feathered.feather_angle);
  feathered.feather_angle = {1.2};
  try {
    flapsim_ros::fromMsg(feathered);
    ADD_FAILURE() << "1 feather angle for 2 strokes accepted";
  } catch (const flapsim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 feather_angle entries for 2 strokes"),
              std::string::npos)
        << e.what();
  }

  flapsim::WingCommand bad = m;
  bad.upstroke_rate = {10};
  try {
    flapsim_ros::fromMsg(bad);
    ADD_FAILURE() << "mismatched arrays accepted";
  } catch (const flapsim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("upstroke_rate 1"), std::string::npos) << e.what();
  }
  bad = m;
  bad.joint_names = {"unit0_wing_left_joint"};
  try {
    flapsim_ros::fromMsg(bad);
    ADD_FAILURE() << "1 joint name for 2 strokes accepted";
  } catch (const flapsim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 joint_names but 2 strokes"), std::string::npos)
        << e.what();
  }
}

TEST(Conversions, WingCommandsAreCheckedAgainstTheModel) {
  auto afc = flapsim::loadCreatureModel(sourcePath("urdf/afc_4.urdf"));
  const flapsim::StrokeCommand ok{30, 10, 0.8};
  auto error = [&](std::vector<std::string> joints, std::vector<flapsim::StrokeCommand> strokes) {
    try {
      flapsim::checkWingCommands(*afc, joints, strokes);
    } catch (const flapsim::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error({}, std::vector<flapsim::StrokeCommand>(8, ok)), "");
  EXPECT_EQ(error({"unit3_wing_right_joint"}, {ok}), "");
  EXPECT_EQ(error({}, {ok, ok}), "2 commands for 8 wing joints");
  EXPECT_EQ(error({"nope"}, {ok}), "no joint 'nope'");
  EXPECT_EQ(error({"unit1_link_joint"}, {ok}), "joint 'unit1_link_joint' is not a wing joint");
  EXPECT_EQ(error({"unit0_wing_left_joint"}, {{30, -1, 0.8}}),
            "joint 'unit0_wing_left_joint': upstroke rate must be finite and >= 0");
  EXPECT_EQ(error({"unit0_wing_left_joint"}, {{std::nan(""), 10, 0.8}}),
            "joint 'unit0_wing_left_joint': downstroke rate must be finite and >= 0");
  EXPECT_EQ(error({"unit0_wing_left_joint"}, {{30, 10, 1.4}}),
            "joint 'unit0_wing_left_joint': amplitude 1.4 rad does not fit inside its limits "
            "[-1.4, 1.4]");
  EXPECT_EQ(error({"unit0_wing_left_joint"}, {{30, 10, 1.39}}), "");
}

flapsim::CreatureState stateOf(const flapsim::CreatureModel& m) {
  flapsim::CreatureState s;
  for (size_t k = 0; k < m.links.size(); ++k) {
    s.link_poses.push_back(flapsim::Pose{Vec3(0.1 * k, 0.2, 1.0 + k), flapsim::Quat::Identity()});
    s.link_twists.emplace_back();
  }
  for (size_t j = 0; j < m.joints.size(); ++j) {
    s.joint_positions.push_back(0.25 + j);
    s.joint_velocities.push_back(-30.0 + j);
    s.joint_efforts.push_back(0.5 - j);
  }
  return s;
}

TEST(Conversions, JointStatesListMovableJointsInUrdfOrder) {
  auto unit = flapsim::loadCreatureModel(sourcePath("urdf/flap_unit.urdf"));
  const ros::Time stamp = flapsim_ros::simTime(20, 1000000);
  sensor_msgs::JointState js = flapsim_ros::jointStateMsg(*unit, stateOf(*unit), stamp);
  EXPECT_EQ(js.header.stamp, stamp);
  ASSERT_EQ(js.name, (std::vector<std::string>{"unit0_wing_left_joint", "unit0_wing_right_joint"}));
  const int left = unit->findJoint("unit0_wing_left_joint");
  EXPECT_EQ(js.position[0], 0.25 + left);
  EXPECT_EQ(js.velocity[0], -30.0 + left);
  EXPECT_EQ(js.effort[0], 0.5 - left);

  auto copter = flapsim::loadCreatureModel(sourcePath("urdf/bamboo_copter.urdf"));
  EXPECT_TRUE(flapsim_ros::jointStateMsg(*copter, stateOf(*copter), stamp).name.empty());
}

TEST(Conversions, OdometryTwistIsInTheChildFrame) {
  auto plate = flapsim::loadCreatureModel(sourcePath("urdf/plate.urdf"));
  flapsim::CreatureState s = stateOf(*plate);
  // yawed by +90 deg, moving along world +x, spinning about world +x
  s.link_poses[0].orientation = flapsim::Quat(std::sqrt(0.5), 0, 0, std::sqrt(0.5));
  s.link_twists[0] = flapsim::Twist{Vec3(2, 0, 0), Vec3(3, 0, 0)};
  const ros::Time stamp = flapsim_ros::simTime(5, 1000000);
  nav_msgs::Odometry o = flapsim_ros::odometryMsg("p1", *plate, s, stamp, "world");
  EXPECT_EQ(o.header.frame_id, "world");
  EXPECT_EQ(o.child_frame_id, "p1/plate");
  EXPECT_EQ(o.header.stamp, stamp);
  EXPECT_EQ(o.pose.pose.position.z, 1.0);
  // world +x is body -y after a +90 deg yaw
  EXPECT_NEAR(o.twist.twist.linear.x, 0.0, 1e-15);
  EXPECT_NEAR(o.twist.twist.linear.y, -2.0, 1e-15);
  EXPECT_NEAR(o.twist.twist.angular.y, -3.0, 1e-15);
}

// The tree robot_state_publisher builds from a URDF and joint_states: world -> root from the
// state, parent -> child from the joint position (a revolute joint turns about its axis after
// its origin), fixed joints apart.
TEST(TfTree, MovingTransformsFollowTheJointsFromTheRoot) {
  auto unit = flapsim::loadCreatureModel(sourcePath("urdf/flap_unit.urdf"));
  flapsim::CreatureState s = stateOf(*unit);
  auto tf = flapsim_ros::movingTransforms("fu", *unit, s, ros::Time(1, 0), "world");
  ASSERT_EQ(tf.size(), 3u);  // the root and two wing joints
  EXPECT_EQ(tf[0].header.frame_id, "world");
  EXPECT_EQ(tf[0].child_frame_id, "fu/unit0_body");
  EXPECT_EQ(tf[0].transform.translation.z, s.link_poses[0].position.z());
  EXPECT_EQ(tf[0].header.stamp, ros::Time(1, 0));
  const int j = unit->findJoint("unit0_wing_left_joint");
  const flapsim::JointModel& joint = unit->joints[j];
  EXPECT_EQ(tf[1].header.frame_id, "fu/unit0_body");
  EXPECT_EQ(tf[1].child_frame_id, "fu/" + unit->links[joint.child_link].name);
  // origin, then the turn by q about the axis: the axis is left unchanged by the turn, and
  // the rotation angle from the origin's orientation is q
  const auto& r = tf[1].transform.rotation;
  const flapsim::Quat q(r.w, r.x, r.y, r.z);
  const double position = s.joint_positions[j];
  EXPECT_NEAR(joint.origin.orientation.angularDistance(q), position, 1e-12);
  EXPECT_NEAR(((joint.origin.orientation.conjugate() * q) * joint.axis - joint.axis).norm(), 0.0,
              1e-12);
  EXPECT_EQ(tf[1].transform.translation.y, joint.origin.position.y());
}

TEST(TfTree, FixedJointsAreTheirOrigins) {
  auto copter = flapsim::loadCreatureModel(sourcePath("urdf/bamboo_copter.urdf"));
  auto fixed = flapsim_ros::fixedTransforms("c", *copter, ros::Time(2, 0));
  ASSERT_EQ(fixed.size(), 2u);
  EXPECT_EQ(fixed[0].header.frame_id, "c/pole");
  EXPECT_EQ(fixed[0].child_frame_id, "c/blade_left");
  EXPECT_EQ(fixed[0].transform.translation.y, 0.08);
  EXPECT_EQ(fixed[0].transform.translation.z, 0.1);
  // rpy 0 0.5236 0 about y: sin(0.2618)
  EXPECT_NEAR(fixed[0].transform.rotation.y, std::sin(0.5235987756 / 2), 1e-12);
  flapsim::CreatureState s = stateOf(*copter);
  auto moving = flapsim_ros::movingTransforms("c", *copter, s, ros::Time(2, 0), "world");
  ASSERT_EQ(moving.size(), 1u);  // the root only
  EXPECT_EQ(moving[0].child_frame_id, "c/pole");
}

// A CAD-style URDF: a massless base_link root fixed to a body whose inertia is a full tensor
// (simulated in its principal frame), a wing on a revolute joint. tf gives the file's frames:
// the body -> wing transform is the file's origin and axis, base_link hangs from the body at
// the inverse of its joint's origin.
TEST(TfTree, LumpedLinksAndTurnedInertiasAreUrdfFrames) {
  const std::string inertia = R"(<inertia ixx="2" ixy="0.5" ixz="0.2" iyy="3" iyz="0" izz="4"/>)";
  auto m = flapsim::parseCreatureModel(
      R"(<robot name="r"><link name="base_link"/>
      <link name="body"><inertial><mass value="1"/>)" +
      inertia + R"(</inertial></link>
      <link name="wing"><inertial><mass value="0.1"/>)" +
      inertia + R"(</inertial></link>
      <joint name="base_joint" type="fixed"><parent link="base_link"/><child link="body"/>
        <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/></joint>
      <joint name="hinge" type="revolute"><parent link="body"/><child link="wing"/>
        <origin xyz="0 0.2 0"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      </robot>)");
  ASSERT_TRUE(m->links[0].rotated());
  auto fixed = flapsim_ros::fixedTransforms("c", *m, ros::Time(2, 0));
  ASSERT_EQ(fixed.size(), 1u);
  EXPECT_EQ(fixed[0].header.frame_id, "c/body");
  EXPECT_EQ(fixed[0].child_frame_id, "c/base_link");
  EXPECT_NEAR(fixed[0].transform.translation.z, -0.1, 1e-15);
  EXPECT_NEAR(fixed[0].transform.rotation.z, -std::sqrt(0.5), 1e-15);  // yaw -90 degrees
  const flapsim::CreatureState s = stateOf(*m);
  auto moving = flapsim_ros::movingTransforms("c", *m, s, ros::Time(2, 0), "world");
  ASSERT_EQ(moving.size(), 2u);
  EXPECT_EQ(moving[0].child_frame_id, "c/body");
  EXPECT_EQ(moving[1].child_frame_id, "c/wing");
  const auto& t = moving[1].transform;
  EXPECT_NEAR(std::hypot(t.translation.x, t.translation.z), 0.0, 1e-15);
  EXPECT_NEAR(t.translation.y, 0.2, 1e-15);
  const flapsim::Quat q(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z);
  const flapsim::Quat expect(Eigen::AngleAxisd(s.joint_positions[0], Vec3::UnitX()));
  EXPECT_NEAR(q.angularDistance(expect), 0.0, 1e-14);
}

// gazebo_msgs semantics: the pose in the frame; the velocities' difference in its axes.
TEST(ReferenceFrame, ToFrameAndBackAreInverse) {
  const flapsim_ros::FrameMotion frame{
      flapsim::Pose{Vec3(1, 2, 3), flapsim::Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))},
      flapsim::Twist{Vec3(1, 0, 0), Vec3(0, 0, 2)}};
  const flapsim_ros::FrameMotion body{flapsim::Pose{Vec3(1, 3, 3), flapsim::Quat::Identity()},
                                      flapsim::Twist{Vec3(1, 5, 0), Vec3(0, 0, 3)}};
  const flapsim_ros::FrameMotion rel = flapsim_ros::toFrame(frame, body);
  // 1 m along world y is 1 m along the frame's x (turned 90 degrees about z)
  EXPECT_NEAR((rel.pose.position - Vec3(1, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(rel.pose.orientation.angularDistance(
                  flapsim::Quat(Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()))),
              0.0, 1e-15);
  // velocity difference (0, 5, 0) in world axes is (5, 0, 0) in the frame's
  EXPECT_NEAR((rel.twist.linear - Vec3(5, 0, 0)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((rel.twist.angular - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
  const flapsim_ros::FrameMotion back = flapsim_ros::fromFrame(frame, rel);
  EXPECT_NEAR((back.pose.position - body.pose.position).norm(), 0.0, 1e-15);
  EXPECT_NEAR(back.pose.orientation.angularDistance(body.pose.orientation), 0.0, 1e-15);
  EXPECT_NEAR((back.twist.linear - body.twist.linear).norm(), 0.0, 1e-14);
  EXPECT_NEAR((back.twist.angular - body.twist.angular).norm(), 0.0, 1e-15);
}

// A wrench given in a link's frame: its force and torque turn with the frame, its point is
// taken from the frame's origin (a {} point is the link's origin, not the world's).
TEST(ReferenceFrame, AWrenchInALinkFrameActsAtThatLinksOrigin) {
  const flapsim::Pose frame{Vec3(0, 0, 3),
                            flapsim::Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))};
  flapsim::ExternalWrench w;
  w.link = "body";
  w.force = Vec3(1, 0, 0);
  w.torque = Vec3(0, 2, 0);
  w.duration = 0.5;
  const flapsim::ExternalWrench world = flapsim_ros::toWorld(w, frame);
  EXPECT_NEAR((world.force - Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((world.torque - Vec3(-2, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(world.point, Vec3(0, 0, 3));
  EXPECT_EQ(world.link, "body");
  EXPECT_EQ(world.duration, 0.5);
}

// apply_wrench's request in core terms: gazebo's start_time (sim time) becomes the wrench's
// start_time in s, zero (the default: the next step) stays zero.
TEST(Conversions, ApplyWrenchRequestKeepsItsStartTimeAndDuration) {
  flapsim::ApplyWrench::Request req;
  req.link = "wing";
  req.reference_point.x = 0.5;
  req.wrench.force.z = 2.0;
  req.wrench.torque.x = -1.0;
  req.duration = ros::Duration(0, 200000000);
  EXPECT_EQ(flapsim_ros::fromMsg(req).start_time, 0.0);
  req.start_time = ros::Time(6, 410000000);
  const flapsim::ExternalWrench w = flapsim_ros::fromMsg(req);
  EXPECT_NEAR(w.start_time, 6.41, 1e-12);
  EXPECT_NEAR(w.duration, 0.2, 1e-12);
  EXPECT_EQ(w.link, "wing");
  EXPECT_EQ(w.point, Vec3(0.5, 0, 0));
  EXPECT_EQ(w.force, Vec3(0, 0, 2));
  EXPECT_EQ(w.torque, Vec3(-1, 0, 0));
}

TEST(Conversions, AeroMarkersAreScaledArrows) {
  flapsim::LinkAero a;
  a.link = 2;
  a.com = Vec3(1, 2, 3);
  a.wrench.force = Vec3(0, 0, 2);
  a.cell_centres = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  a.cell_forces = {Vec3(0.1, 0, 0), Vec3(0, 0, 0), Vec3(0, -0.2, 0)};
  flapsim_ros::MarkerParams mp;
  mp.scale = 0.5;
  mp.width = 0.01;
  auto m = flapsim_ros::aeroMarkers("fu", {a}, mp, ros::Time(2, 0), "world");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].ns, "fu");
  EXPECT_EQ(m[0].id, 2);
  EXPECT_EQ(m[0].type, visualization_msgs::Marker::ARROW);
  EXPECT_EQ(m[0].header.frame_id, "world");
  ASSERT_EQ(m[0].points.size(), 2u);
  EXPECT_EQ(m[0].points[0].z, 3.0);
  EXPECT_EQ(m[0].points[1].z, 4.0);  // 3 + 0.5 m/N * 2 N
  EXPECT_EQ(m[0].scale.x, 0.01);

  mp.per_cell = true;
  m = flapsim_ros::aeroMarkers("fu", {a}, mp, ros::Time(2, 0), "world");
  ASSERT_EQ(m.size(), 3u);  // the zero-force cell has no arrow
  EXPECT_EQ(m[1].ns, "fu/cells");
  EXPECT_EQ(m[1].points[1].x, 0.05);
  EXPECT_EQ(m[2].points[0].x, 2.0);
  EXPECT_EQ(m[2].points[1].y, -0.1);

  a.wrench.force = Vec3::Zero();
  mp.per_cell = false;
  EXPECT_TRUE(flapsim_ros::aeroMarkers("fu", {a}, mp, ros::Time(2, 0), "world").empty());
}

// ---- driving: set_state, apply_wrench, imu ------------------------------------------------

// An accelerometer reads acceleration less gravity in its own axes, gyros the angular
// velocity in its own axes: after a +90 deg roll about x the body's y axis is the world's z,
// so at rest +g reads along body y, and a yaw rate too. Noise adds sigma x the drawn sample on
// each axis; the orientation turns by the rotation vector sigma x the samples in the body's
// axes; the covariances are sigma^2.
// The IMU's noise is a function of the seed, the creature and the instant: a message made
// again for the same instant (a subscriber connecting) carries the same noise, so the noise a
// run's controller reads does not hang on when nodes connect; another instant, creature or
// seed draws other noise.
TEST(Imu, NoiseIsTheSameForEveryMessageOfOneInstant) {
  flapsim_ros::CreatureSnapshot s;
  s.name = "p";
  s.model = flapsim::loadCreatureModel(sourcePath("urdf/plate.urdf"));
  s.state.link_poses = {flapsim::Pose{Vec3(1, 2, 3), flapsim::Quat::Identity()}};
  s.state.link_twists = {flapsim::Twist{}};
  s.gravity = Vec3(0, 0, -9.81);
  s.stamp = ros::Time(5, 1000000);
  flapsim_ros::ImuParams params;
  params.orientation_noise = params.angular_velocity_noise = 0.05;
  params.linear_acceleration_noise = 0.1;
  const flapsim_ros::ImuNoiseSource imu(params);
  const auto rate = [](const sensor_msgs::Imu& m) {
    return Vec3(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z);
  };
  const Vec3 first = rate(imu.message(s));
  EXPECT_GT(first.norm(), 0.0);
  EXPECT_EQ(rate(imu.message(s)), first);  // made again: the same bits
  flapsim_ros::CreatureSnapshot later = s, other = s;
  later.stamp = ros::Time(5, 2000000);
  other.name = "q";
  EXPECT_NE(rate(imu.message(later)), first);
  EXPECT_NE(rate(imu.message(other)), first);
  params.seed = 1;
  EXPECT_NE(rate(flapsim_ros::ImuNoiseSource(params).message(s)), first);
}

TEST(Imu, ReadsSpecificForceAndRatesInBodyAxesWithNoise) {
  auto model = flapsim::loadCreatureModel(sourcePath("urdf/plate.urdf"));
  flapsim::CreatureState s;
  const flapsim::Quat roll(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()));
  s.link_poses = {flapsim::Pose{Vec3(1, 2, 3), roll}};
  s.link_twists = {flapsim::Twist{Vec3::Zero(), Vec3(0, 0, 2)}};
  const Vec3 g(0, 0, -9.81);
  sensor_msgs::Imu m = flapsim_ros::imuMsg("p", *model, s, Vec3::Zero(), g, ros::Time(5));
  EXPECT_EQ(m.header.frame_id, "p/plate");
  EXPECT_EQ(m.header.stamp, ros::Time(5));
  EXPECT_NEAR(m.linear_acceleration.x, 0.0, 1e-12);
  EXPECT_NEAR(m.linear_acceleration.y, 9.81, 1e-12);
  EXPECT_NEAR(m.linear_acceleration.z, 0.0, 1e-12);
  EXPECT_NEAR(m.angular_velocity.y, 2.0, 1e-12);
  EXPECT_NEAR(m.orientation.x, std::sqrt(0.5), 1e-12);
  EXPECT_EQ(m.linear_acceleration_covariance[0], 0.0);
  // free fall reads nothing
  m = flapsim_ros::imuMsg("p", *model, s, g, g, ros::Time(5));
  EXPECT_NEAR(m.linear_acceleration.y, 0.0, 1e-12);
  // noise: every sample 1.0 adds sigma on each axis
  const flapsim::ImuNoise noise{0.03, 0.01, 0.2};
  m = flapsim_ros::imuMsg("p", *model, s, g, g, ros::Time(5), noise, [] { return 1.0; });
  EXPECT_NEAR(m.linear_acceleration.x, 0.2, 1e-12);
  EXPECT_NEAR(m.angular_velocity.x, 0.01, 1e-12);
  EXPECT_NEAR(m.angular_velocity.y, 2.01, 1e-12);
  EXPECT_NEAR(m.linear_acceleration_covariance[4], 0.04, 1e-15);
  EXPECT_NEAR(m.angular_velocity_covariance[8], 1e-4, 1e-18);
  EXPECT_NEAR(m.orientation_covariance[0], 9e-4, 1e-18);
  const Vec3 n(0.03, 0.03, 0.03);
  const flapsim::Quat sensed = roll * flapsim::Quat(Eigen::AngleAxisd(n.norm(), n.normalized()));
  const flapsim::Quat got(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z);
  EXPECT_NEAR(got.angularDistance(sensed), 0.0, 1e-12);
  EXPECT_NEAR(got.angularDistance(roll), n.norm(), 1e-12);
  // the reading back in core terms
  const flapsim::ImuReading back = flapsim_ros::fromMsg(m);
  EXPECT_NEAR(back.orientation.angularDistance(sensed), 0.0, 1e-12);
  EXPECT_NEAR(back.angular_velocity.y(), 2.01, 1e-12);
  m.angular_velocity.z = std::nan("");
  EXPECT_THROW(flapsim_ros::fromMsg(m), flapsim::InputError);
}

// set_state's joint lists: named joints take the values, the others keep the current ones;
// bad names and lengths are named.
TEST(SetStateRequest, NamedJointsTakeTheirValuesOthersKeepTheirs) {
  auto model = flapsim::loadCreatureModel(sourcePath("urdf/flap_unit.urdf"));
  flapsim::CreatureState now;
  now.joint_positions = {0.1, 0.2};
  now.joint_velocities = {1.0, 2.0};
  flapsim::SetState::Request req;
  req.joint_names = {"unit0_wing_right_joint"};
  req.joint_positions = {-0.5};
  flapsim::StateRequest r = flapsim_ros::stateRequest(*model, now, req);
  EXPECT_EQ(r.joint_positions, (std::vector<double>{0.1, -0.5}));
  EXPECT_EQ(r.joint_velocities, (std::vector<double>{1.0, 2.0}));
  req.joint_names.clear();
  req.joint_positions.clear();
  EXPECT_TRUE(flapsim_ros::stateRequest(*model, now, req).joint_positions.empty());
  auto error = [&](const flapsim::SetState::Request& q) {
    try {
      flapsim_ros::stateRequest(*model, now, q);
    } catch (const flapsim::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  req.joint_names = {"unit0_wing_right_joint", "unit0_wing_right_joint"};
  req.joint_positions = {0, 0};
  EXPECT_NE(error(req).find("named twice"), std::string::npos) << error(req);
  req.joint_names = {"tail_joint"};
  req.joint_positions = {0};
  EXPECT_NE(error(req).find("'tail_joint'"), std::string::npos) << error(req);
  req.joint_names = {"unit0_wing_right_joint"};
  req.joint_velocities = {0, 0};
  EXPECT_NE(error(req).find("2 joint_velocities for 1 joint_names"), std::string::npos)
      << error(req);
}

}  // namespace
