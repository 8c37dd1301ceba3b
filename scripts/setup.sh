#!/usr/bin/env bash
# Installs what multifluid needs to build, test and run, from Debian 12's packages.
# Run as root. Does nothing (and needs no network) when everything is already there.
#   --farm  also Slurm and munge, for `multifluid farm` and its test (a local single-node Slurm,
#           scripts/slurm_local.sh); users without a farm do not need them.
#   --with-blender  also Blender (Debian 12: 3.4), for `multifluid export blender`
#           and its test.
set -euo pipefail
farm=0
blender=0
for a in "$@"; do
  case "$a" in
    --farm) farm=1 ;;
    --with-blender) blender=1 ;;
    *) echo "setup: unknown option '$a' (options: --farm, --with-blender)" >&2; exit 2 ;;
  esac
done
packages=(
  build-essential cmake pkg-config ccache
  libopenvdb-dev libtbb-dev libboost-iostreams-dev libeigen3-dev libfmt-dev libtomlplusplus-dev
  libembree-dev libosmesa6-dev libopenimageio-dev
  ffmpeg gnuplot-nox
  libgtest-dev libbenchmark-dev
  libcli11-dev libxxhash-dev python3 clang libclang-rt-14-dev
)
[ "$farm" -eq 0 ] || packages+=(slurmctld slurmd slurm-client munge)
[ "$blender" -eq 0 ] || packages+=(blender)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing packages: ${missing[*]}; run this script as root (or install them)" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
