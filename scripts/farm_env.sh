#!/bin/sh
# roslaunch env-loader of a farm worker machine (evolve_farm.launch machines:=...): sets up
# the ROS environment there, then runs the command roslaunch gives it.
#   FLAPSIM_SETUP  setup.sh of the workspace that holds flapsim on that machine
#                  (default: ~/flapsim_ws/devel/setup.sh; none needed for a Debian install
#                  of flapsim under /usr)
#   ROS_IP         the address the evolve machine reaches this one at (default: the
#                  first address of `hostname -I`)
setup="${FLAPSIM_SETUP:-$HOME/flapsim_ws/devel/setup.sh}"
if [ -f "$setup" ]; then
  . "$setup"
fi
if [ -z "$ROS_IP" ] && [ -z "$ROS_HOSTNAME" ]; then
  ROS_IP="$(hostname -I | cut -d' ' -f1)"
  export ROS_IP
fi
exec "$@"
