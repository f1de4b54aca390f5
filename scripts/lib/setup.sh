# shellcheck shell=bash disable=SC2034,SC2119,SC2120
# Shared set-up of scripts/test and scripts/demo (sourced, not run).
#
# On a Debian bookworm machine (root, or a user with sudo) it installs the Debian packages that
# are missing, builds a catkin workspace around this checkout and builds the package.
# The workspace is $AMCR_WS, by default <repo>/.build/ws (ignored by git; .build/CATKIN_IGNORE
# keeps catkin from looking into it), with src/amcr a symlink to the checkout.
#
# Functions: amcr_stage, amcr_die, amcr_install_packages, amcr_install_clang, amcr_environment,
# amcr_make_workspace, amcr_catkin_make, amcr_source_devel, amcr_setup (all of the set-up).

AMCR_REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd -P)"
AMCR_WS="$(realpath -m "${AMCR_WS:-$AMCR_REPO/.build/ws}")"
AMCR_JOBS="${AMCR_JOBS:-2}"

# Debian packages: Debian's ROS 1 build (catkin, roscpp, nodelet, image_transport, cv_bridge, ...)
# plus the libraries this package uses. opencv-doc provides the silhouettes and photos of the demo sequence. The benchmark's
# peers and their tests use OpenCV's rgbd (contrib: LINE-2D) and shape (shape contexts) modules;
# libopencv-dev depends on both, named here because the tests need them. rviz, xvfb and x11-apps
# (xwd) run RViz in a virtual display for test/ros/rviz_screenshot.py.
AMCR_PACKAGES=(
  build-essential ros-base-dev rosbash libimage-transport-dev libcv-bridge-dev
  libtf2-ros-dev libtf2-eigen-dev python3-rostest python3-cv-bridge python3-opencv
  libopencv-dev libeigen3-dev libgtest-dev python3-dynamic-reconfigure
  libdiagnostic-updater-dev libnodeletlib-dev librosbag-dev opencv-doc libbenchmark-dev
  pluginlib-dev ros-message-generation libstd-srvs-dev libgeometry-msgs-dev libsensor-msgs-dev
  librostest-dev python3-rosbag python3-diagnostic-msgs python3-std-srvs python3-rosparam catkin-lint
  libimage-geometry-dev libvisualization-msgs-dev python3-visualization-msgs python3-tf2-ros
  libopencv-contrib-dev libopencv-shape-dev nlohmann-json3-dev libyaml-cpp-dev libboost-program-options-dev
  rviz xvfb x11-apps
)

# scripts/test --sanitize and scripts/fuzz: clang with its sanitizer and libFuzzer runtimes. On
# bookworm the runtimes (libclang_rt.asan, libclang_rt.fuzzer, ...) are in libclang-rt-dev
# (libclang-rt-14-dev); on Ubuntu 20.04 they come with clang (clang-10 -> libclang-common-10-dev),
# where libclang-rt-dev does not exist: amcr_install_clang adds it only when apt knows it.
AMCR_CLANG_PACKAGES=(clang cmake)

# Debian's python3, never a pyenv/venv one: Debian's ROS Python modules are installed for it alone.
AMCR_CMAKE_ARGS=(-DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3)

AMCR_STAGE=""
amcr_stage() {
  AMCR_STAGE="$*"
  printf '\n==== %s ====\n' "$*"
}

amcr_die() {
  printf 'error: %s\n' "$*" >&2
  exit 1
}

# Installs the packages named (default: AMCR_PACKAGES) that are not installed yet; does nothing
# (and needs no network or root) when all are there.
amcr_install_packages() {
  amcr_stage "Debian packages"
  local wanted=("$@") missing=() pkg status
  ((${#wanted[@]} > 0)) || wanted=("${AMCR_PACKAGES[@]}")
  for pkg in "${wanted[@]}"; do
    status="$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)"
    [[ "$status" == installed ]] || missing+=("$pkg")
  done
  if ((${#missing[@]} == 0)); then
    echo "all ${#wanted[@]} packages are installed"
    return 0
  fi
  echo "missing: ${missing[*]}"
  local sudo=()
  if ((EUID != 0)); then
    command -v sudo >/dev/null || amcr_die "not root and no sudo: install as root: apt-get install ${missing[*]}"
    sudo=(sudo)
  fi
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -q update
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -q install -y --no-install-recommends \
    -o Dpkg::Use-Pty=0 "${missing[@]}"
}

# AMCR_CLANG_PACKAGES, plus libclang-rt-dev where apt knows it (bookworm); then checks that clang++
# links a libFuzzer target with AddressSanitizer and UBSan, and says why not when it cannot.
amcr_install_clang() {
  local packages=("${AMCR_CLANG_PACKAGES[@]}")
  local candidate=(sed -n 's/^ *Candidate: \([^(]\)/\1/p')
  if [[ -z "$(apt-cache policy clang 2>/dev/null | "${candidate[@]}")" ]] && command -v apt-get >/dev/null; then
    # A fresh machine's package lists may be empty: then apt knows neither package.
    local sudo=()
    ((EUID == 0)) || sudo=(sudo)
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -q update || true
  fi
  if [[ -n "$(apt-cache policy libclang-rt-dev 2>/dev/null | "${candidate[@]}")" ]]; then
    packages+=(libclang-rt-dev)  # Debian bookworm: the runtime is only recommended by clang
  fi
  amcr_install_packages "${packages[@]}"
  local probe
  probe="$(mktemp -d)"
  echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' >"$probe/probe.cpp"
  if ! clang++ -fsanitize=fuzzer,address,undefined -o "$probe/probe" "$probe/probe.cpp" >"$probe/log" 2>&1; then
    cat "$probe/log" >&2
    rm -rf "$probe"
    amcr_die "clang++ ($(command -v clang++ || echo 'not found')) cannot link a libFuzzer target with the" \
      "sanitizers (-fsanitize=fuzzer,address,undefined: the libclang_rt runtimes are missing). On Debian install" \
      "clang and libclang-rt-dev, on Ubuntu 20.04 clang (libclang-common-10-dev)"
  fi
  rm -rf "$probe"
}

# The environment every catkin and ROS command here runs in: Debian's /usr/bin first on PATH (its
# python3 is the one with the ROS modules), a master on this machine, ROS_HOME in the workspace.
amcr_environment() {
  export PATH="/usr/bin:/bin:/usr/sbin:/sbin:$PATH"
  unset PYTHONHOME VIRTUAL_ENV PYENV_VERSION ROS_HOSTNAME
  export ROS_MASTER_URI=http://127.0.0.1:11311
  export ROS_IP=127.0.0.1
  export ROS_HOME="$AMCR_WS/.ros_home"
  mkdir -p "$ROS_HOME"
}

amcr_make_workspace() {
  amcr_stage "Workspace $AMCR_WS"
  # Inside the checkout the workspace lives under .build/, which catkin must not search.
  mkdir -p "$AMCR_REPO/.build"
  touch "$AMCR_REPO/.build/CATKIN_IGNORE"
  mkdir -p "$AMCR_WS/src"
  local link="$AMCR_WS/src/amcr"
  if [[ -e "$link" && ! -L "$link" ]]; then
    amcr_die "$link exists and is not a symlink; move it away or set AMCR_WS"
  fi
  if [[ "$(readlink "$link" 2>/dev/null || true)" != "$AMCR_REPO" ]]; then
    ln -sfn "$AMCR_REPO" "$link"
  fi
  # A build tree configured for another source path (moved workspace) cannot be reused.
  local cache="$AMCR_WS/build/CMakeCache.txt"
  if [[ -f "$cache" ]] && ! grep -qxF "CMAKE_HOME_DIRECTORY:INTERNAL=$AMCR_WS/src" "$cache"; then
    echo "build/ was configured elsewhere: removing build/ and devel/"
    rm -rf "$AMCR_WS/build" "$AMCR_WS/devel"
  fi
  echo "src/amcr -> $(readlink "$link")"
}

# catkin_make [targets...] in the workspace, with Debian's python and $AMCR_JOBS jobs.
amcr_catkin_make() {
  (cd "$AMCR_WS" && catkin_make "${AMCR_CMAKE_ARGS[@]}" -j"$AMCR_JOBS" "$@")
}

# setup.bash reads unset variables: source it with `set -u` off.
amcr_source_devel() {
  [[ -f "$AMCR_WS/devel/setup.bash" ]] || amcr_die "no $AMCR_WS/devel/setup.bash: the build did not finish"
  set +u
  # shellcheck disable=SC1091
  source "$AMCR_WS/devel/setup.bash"
  set -u
}

# All of the set-up: packages, environment, workspace, build.
amcr_setup() {
  amcr_install_packages
  amcr_environment
  amcr_make_workspace
  amcr_stage "Build (catkin_make)"
  amcr_catkin_make
  amcr_source_devel
}
