#!/bin/bash
# Installs the Debian 12 packages flapsim needs to build, run and test (ROS Noetic as
# Debian ships it: everything under /usr). Uses sudo when not root; installs only what
# is missing.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake pkg-config
  # ROS 1 (Debian's packaging)
  catkin ros-core ros-core-dev ros-message-generation python3-gencpp
  libroscpp-dev librosbag-dev libtf2-ros-dev libtf2-msgs-dev libtf2-geometry-msgs-dev
  libstd-msgs-dev libstd-srvs-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libvisualization-msgs-dev libros-rosgraph-msgs-dev libdiagnostic-msgs-dev
  python3-rosbag python3-rosnode python3-rostopic python3-roslaunch python3-rosservice
  python3-rostest librostest-dev python3-rospy python3-yaml
  # live parameters of the simulator node (cfg/Flapsim.cfg)
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  # simulator node: Python message classes, so rostopic/rosservice/rosbag can show them
  python3-std-srvs python3-geometry-msgs python3-sensor-msgs python3-nav-msgs python3-tf2-msgs
  python3-visualization-msgs python3-diagnostic-msgs
  # physics, robot description, configuration
  libbullet-dev libeigen3-dev liburdfdom-dev libtinyxml2-dev libconsole-bridge-dev
  libyaml-cpp-dev
  # convex decomposition of URDF meshes: HACD, in Bullet's extras
  libbullet-extras-dev
  # URDF meshes: assimp reads STL/OBJ/DAE; roslib resolves package:// URIs (ros::package)
  libassimp-dev libroslib-dev
  # tests and plots
  libgtest-dev googletest gnuplot-nox
  # seeing it: rviz, rosrun, headless X for rviz, screenshots, movies and their checks
  rviz rosbash xvfb xauth imagemagick ffmpeg python3-pil
  # the tf tree as users inspect it: view_frames.py and echo.py (which needs numpy)
  tf2-tools python3-numpy
  # side-by-side benchmark against MuJoCo (bench/mujoco_bench.cpp)
  libmujoco-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_deps: done"
