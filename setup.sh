#!/bin/sh
# setup.sh - one command on a fresh Debian 12 machine: install the
# dependencies (apt-get; run as root or with sudo available), build, and run
# the default study (strip3), leaving its results and plots in out/strip3/.
set -e
cd "$(dirname "$0")"
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends $(cat packages.txt)
autoreconf -fi
./configure -q
make -j2
./src/smoothfold run studies/strip3.cfg -o out/strip3
./src/smoothfold plot out/strip3
echo "setup.sh: built src/smoothfold; default study results in out/strip3/ (see docs/reference/output-files.md)"
