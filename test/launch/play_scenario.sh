#!/usr/bin/env bash
# rostest helper: the offline workflow a team uses on a recording, from scratch —
# make_scenario writes a bag with its calibration files, calibrate_field solves the camera
# pose from the landmark correspondences, calibrate_synthetic the colour table of the same
# scenario, then the bag is played into the running vision system (which waits for both
# files). Usage: play_scenario.sh PRESET FRAMES DIR [roslaunch's __name:= ... ignored]
set -euo pipefail
export PATH="/usr/bin:/bin:$PATH"
preset="$1" frames="$2" dir="$3"
rm -rf "$dir" && mkdir -p "$dir"
rosrun soccer_vision make_scenario --preset "$preset" --frames "$frames" --out "$dir/scenario.bag" \
  --cameras 0 --compression lz4 --start "$(date +%s)"
rosrun soccer_vision calibrate_field --camera-info "$dir/camera_info.yaml" --points "$dir/field_points.yaml" \
  --out "$dir/camera_pose.partial.yaml"
mv "$dir/camera_pose.partial.yaml" "$dir/camera_pose.yaml"
rosrun soccer_vision calibrate_synthetic --scenario "$preset" --camera 0 --out "$dir/table.svct"
sleep 2  # the nodelets pick the files up
exec rosbag play --quiet "$dir/scenario.bag"
