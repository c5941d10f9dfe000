# Shared by scripts/demo and scripts/test: install what is missing, build the catkin
# workspace out of tree (.ws/, ignored by git). Sourced, not run.

# Debian's ROS Python modules are only visible to /usr/bin/python3; another python3 first
# on PATH breaks catkin ("No module named 'ament_package'") and rostest.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:$PATH"
export PYTHONNOUSERSITE=1

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="$REPO/.ws"

DEBIAN_PACKAGES=(
  build-essential cmake catkin ros-base-dev ros-message-generation ros-message-runtime
  libnodeletlib-dev libnodeletlib-tools python3-nodelet libcv-bridge-dev
  libimage-transport-dev libcamera-info-manager-dev libcamera-calibration-parsers-dev
  libtf2-ros-dev libtf2-geometry-msgs-dev libdynamic-reconfigure-config-init-mutex-dev
  python3-dynamic-reconfigure libdiagnostic-updater-dev libdiagnostic-msgs-dev
  libsensor-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev python3-sensor-msgs
  python3-geometry-msgs python3-visualization-msgs python3-diagnostic-msgs python3-std-msgs
  ros-std-msgs librosbag-dev python3-rosbag librostest-dev python3-rostest
  python3-roslaunch python3-rostopic rosbash rosout libopencv-dev libeigen3-dev
  libyaml-cpp-dev nlohmann-json3-dev libgtest-dev rviz xvfb xauth
)
DEBIAN_PACKAGES+=( libaravis-dev aravis-tools libopencv-videoio-dev pkg-config libglib2.0-dev linux-libc-dev )
DEBIAN_PACKAGES+=( libx11-dev )  # the rviz screenshot test reads the X display
DEBIAN_PACKAGES+=( python3-yaml )  # scripts/nodelet_docs and test/docs read cfg/*.params.yaml
DEBIAN_PACKAGES+=( libcli11-dev )  # the tools' command lines
DEBIAN_PACKAGES+=( libprotobuf-dev protobuf-compiler python3-protobuf )  # the SSL packets (src/ssl, proto/) and their Python decoding tests
DEBIAN_PACKAGES+=( libcpp-httplib-dev )  # the calibration UI's HTTP server
DEBIAN_PACKAGES+=( chromium chromium-driver python3-selenium )  # the calibration UI's browser test
DEBIAN_PACKAGES+=( libstd-srvs-dev python3-std-srvs )  # Segmentation's ~reset_online_calibration (std_srvs/Trigger)
DEBIAN_PACKAGES+=( python3-tf2-msgs )  # the live tests read /tf
DEBIAN_PACKAGES+=( ccache )  # rebuilds of other checkouts and of the sanitizer workspace are cheap
DEBIAN_PACKAGES+=( clang-format )  # test/style checks that the C++ sources are formatted

install_missing() {
  local missing=()
  local pkg
  for pkg in "${DEBIAN_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "== installing ${#missing[@]} Debian package(s): ${missing[*]}"
  local sudo=()
  [ "$(id -u)" -ne 0 ] && sudo=(sudo)
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# Builds the package; extra make targets (e.g. "tests") may be given.
build_workspace() {
  # The package directory links every top-level entry of the repository but the workspace
  # itself: a link to the repository root would make a file-system loop (.ws inside it)
  # that rosrun's find and other crawlers trip over.
  local pkg="$WS/src/soccer_vision" entry
  [ -L "$pkg" ] && rm "$pkg"
  mkdir -p "$pkg"
  for entry in "$REPO"/*; do ln -sfn "$entry" "$pkg/"; done
  find "$pkg" -maxdepth 1 -xtype l -delete  # entries removed from the repository
  # ccache, where the machine has it, makes rebuilds of other checkouts cheap.
  # CCACHE_BASEDIR makes its keys independent of where the checkout lies.
  local launcher=()
  command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$REPO}"
  (cd "$WS" && catkin_make -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON "${launcher[@]}" -j2 "$@" \
      > "$WS/build.log" 2>&1) || { tail -n 60 "$WS/build.log"; echo "== build failed (full log: $WS/build.log)"; return 1; }
  grep -E "warning:" "$WS/build.log" | sort -u | head -n 20 || true
}

source_workspace() {
  set +u
  # shellcheck disable=SC1091
  source "$WS/devel/setup.bash"
  set -u
}

# What the vision system needs to know about a scenario preset file: its marker pattern
# (two_tag unless it says so) and the tracker's measurement_offset (a blurred frame shows
# the middle of its exposure: shownTimeAfterStamp in field_renderer.h).
scenario_pattern() {
  local pattern
  pattern="$(sed -n 's/^pattern:[[:space:]]*\([A-Za-z_]*\).*/\1/p' "$1" 2>/dev/null | head -n 1)"
  echo "${pattern:-two_tag}"
}
scenario_field() {
  local field
  field="$(sed -n 's/^field:[[:space:]]*\([^[:space:]#]*\).*/\1/p' "$1" 2>/dev/null | head -n 1)"
  echo "${field:-div_b}"
}
scenario_measurement_offset() {
  /usr/bin/python3 -c 'import sys, yaml
s = (yaml.safe_load(open(sys.argv[1])) or {}).get("sensor") or {}
print(s.get("exposure", 0.004) / 2 if s.get("blur_samples", 1) > 1 else 0)' "$1" 2>/dev/null || echo 0
}
