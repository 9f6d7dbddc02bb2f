#!/usr/bin/env bash
# Fetch real point sets and meshes from Debian packages into datasets/real/ (gitignored).
#
#   datasets/fetch_real_data.sh           fetch what is missing
#   datasets/fetch_real_data.sh --force   fetch again and overwrite
#
# Sources (no download outside Debian's archive):
#   libcgal-demo   CGAL's demo/example data: data.tar.gz inside the .deb holds data/points_3/
#                  (scanned and synthetic point sets: .xyz .pwn .ply .off) and data/meshes/.
#   glmark2-data   a Stanford bunny as Wavefront OBJ (optional).
# Idempotent: files already in datasets/real/ are kept unless --force is given.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# place, place_from_archive, report_placed
source "${script_dir}/../scripts/fetch_common.sh"
dest="${script_dir}/real"
force=0
if [[ "${1:-}" == "--force" ]]; then force=1; fi

# Paths inside libcgal-demo's data.tar.gz. Chosen for variety of size and shape; files that
# are not point sets (points_3/triangles.xyz is a triangle soup) or are 3-point examples are
# left out.
cgal_files=(
  data/points_3/building.ply          # LiDAR-like building scan, 100k points
  data/points_3/ball.ply
  data/points_3/b9_training.ply       # binary PLY with labels
  data/points_3/hippo1.ply
  data/points_3/spheres.ply
  data/points_3/circles.ply
  data/points_3/radar.xyz
  data/points_3/sphere_20k.xyz
  data/points_3/poste_france.xyz
  data/points_3/point_set_3.xyz
  data/points_3/kitten.xyz
  data/points_3/blobby.xyz
  data/points_3/oneK.xyz
  data/points_3/cube.pwn              # 50k points with normals
  data/points_3/oni.pwn
  data/points_3/kitten.off            # vertices only (0 faces)
  data/meshes/bunny00.off
  data/meshes/refined_elephant.off
  data/meshes/armadillo.off
  data/meshes/fandisk_large.off
  data/meshes/ChineseDragon-10kv.off
)
glmark_files=(usr/share/glmark2/models/bunny.obj)

mkdir -p "${dest}"

all_present() {
  local f
  for f in "$@"; do [[ -s "${dest}/$(basename "${f}")" ]] || return 1; done
  return 0
}

work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT

# apt-get download into the current directory; refresh the package lists only if needed.
download() {
  local package="$1"
  if (cd "${work}" && apt-get download "${package}") >/dev/null 2>"${work}/apt.log"; then
    return 0
  fi
  echo "apt-get download ${package} failed; running apt-get update and retrying" >&2
  apt-get update >/dev/null 2>>"${work}/apt.log" || true
  (cd "${work}" && apt-get download "${package}") >/dev/null 2>>"${work}/apt.log"
}

placed=()

fetch_cgal() {
  if [[ ${force} -eq 0 ]] && all_present "${cgal_files[@]}"; then
    echo "libcgal-demo data already in ${dest} (use --force to fetch again)"
    return 0
  fi
  if ! download libcgal-demo; then
    echo "error: could not download libcgal-demo:" >&2
    cat "${work}/apt.log" >&2
    exit 1
  fi
  dpkg -x "${work}"/libcgal-demo_*.deb "${work}/cgal"
  # The data is not loose in the package: it is one more archive, data.tar.gz.
  local archive
  archive="$(find "${work}/cgal" -name data.tar.gz -print -quit)"
  if [[ -z "${archive}" ]]; then
    echo "error: no data.tar.gz in libcgal-demo (package layout changed?)" >&2
    exit 1
  fi
  mkdir -p "${work}/cgal-data"
  place_from_archive "${archive}" "${work}/cgal-data" "warning: " "${cgal_files[@]}"
}

fetch_glmark() {
  if [[ ${force} -eq 0 ]] && all_present "${glmark_files[@]}"; then
    echo "glmark2-data bunny already in ${dest}"
    return 0
  fi
  if ! download glmark2-data; then
    echo "note: glmark2-data is not available here; skipping the OBJ bunny (optional)"
    return 0
  fi
  dpkg -x "${work}"/glmark2-data_*.deb "${work}/glmark"
  local f
  for f in "${glmark_files[@]}"; do
    if [[ -f "${work}/glmark/${f}" ]]; then
      place "${work}/glmark/${f}"
    else
      echo "note: ${f} is not in this glmark2-data version; skipped"
    fi
  done
}

fetch_cgal
fetch_glmark

if [[ ${#placed[@]} -gt 0 ]]; then
  echo "placed in ${dest}:"
  report_placed "  " 28
else
  echo "nothing to do; ${dest} is complete"
fi
