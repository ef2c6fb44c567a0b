#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), links the packages into a catkin workspace at
# .ws/ and builds it (Release). Safe to run again: it only installs and rebuilds what changed.
# Usage: scripts/setup.sh   (as root, or with sudo available for apt-get)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HYBRID_SLAM_WS:-$ROOT/.ws}"

DEB_PACKAGES=(
  build-essential cmake pkg-config git
  ros-core-dev ros-base-dev catkin ros-message-generation ros-message-runtime
  libroscpp-dev librosbag-dev librostest-dev python3-rostest python3-rosbag python3-rospy
  python3-roslaunch python3-rosnode python3-rostopic python3-rosservice python3-rosparam
  libtf2-ros-dev libtf2-geometry-msgs-dev libtf2-eigen-dev python3-tf2-ros tf2-tools
  libstd-msgs-dev libstd-srvs-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libvisualization-msgs-dev libros-rosgraph-msgs-dev libactionlib-dev libactionlib-msgs-dev python3-actionlib
  ros-robot-state-publisher rosbash
  python3-sensor-msgs python3-nav-msgs python3-geometry-msgs python3-std-msgs python3-visualization-msgs
  python3-tf2-msgs python3-rosgraph-msgs python3-std-srvs python3-actionlib-msgs
  libbullet-dev liburdfdom-dev libopencv-dev libopencv-contrib-dev libeigen3-dev libyaml-cpp-dev
  libgtest-dev libbenchmark-dev clang-14 libclang-rt-14-dev
  rviz librviz-dev xvfb x11-apps xdotool imagemagick python3-yaml python3-numpy python3-matplotlib python3-scipy python3-opencv
  python3-setuptools python3-catkin-pkg
)

missing=()
for p in "${DEB_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing ${#missing[@]} Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# catkin does not descend below a folder that holds a package.xml, so the root package and the
# package folders are linked side by side into the workspace.
mkdir -p "$WS/src"
ln -sfn "$ROOT" "$WS/src/hybrid_slam"
for pkg in "$ROOT"/*/package.xml; do
  dir="$(dirname "$pkg")"
  ln -sfn "$dir" "$WS/src/$(basename "$dir")"
done
# Remove links to packages that no longer exist.
for link in "$WS"/src/*; do
  [ -L "$link" ] && [ ! -e "$link" ] && rm -f "$link"
done

cd "$WS"
# Debian's ROS lives in /usr; use the system python that has the ROS modules, not a pyenv one.
export PATH="/usr/bin:$PATH"
catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON -j2 "$@"
echo "[setup] built workspace $WS; now: source $WS/devel/setup.bash"
