# shellcheck shell=bash
# Sourced by the scripts that run LAMMPS: installs Debian's lammps if it is missing, and lets
# OpenMPI (LAMMPS is an MPI program) start as root, which it refuses otherwise.
if ! command -v lmp >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "installing Debian's lammps" >&2
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends lammps >&2
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
