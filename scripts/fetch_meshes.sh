#!/usr/bin/env bash
# Copy real triangle meshes for the raycast suite into datasets/real/meshes/ (gitignored, as
# all of datasets/real/: never commit them). Sources are Debian packages, installed with
# apt-get when missing (no other download):
#   libcgal-demo   CGAL's example data (/usr/share/doc/libcgal-dev/data.tar.gz, data/meshes/)
#   glmark2-data   a Stanford bunny as Wavefront OBJ (/usr/share/glmark2/models/bunny.obj)
#
#   scripts/fetch_meshes.sh           fetch what is missing
#   scripts/fetch_meshes.sh --force   copy again
# Idempotent. Exits non-zero only when no mesh at all could be placed.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/fetch_common.sh  # place, place_from_archive, report_placed
dest=datasets/real/meshes
force=0
[[ "${1:-}" == "--force" ]] && force=1

# Varied in size (16k to 89k triangles), shape and file format (OFF, STL, OBJ):
cgal_meshes=(
  data/meshes/refined_elephant.off  # 88 928 triangles, smooth organic
  data/meshes/armadillo.off         # 52 000 triangles, Stanford armadillo
  data/meshes/fandisk_large.off     # 31 682 triangles, CAD part with sharp creases
  data/meshes/pig.stl               # binary STL, 16 848 triangles (tests the STL path)
)
glmark_meshes=(usr/share/glmark2/models/bunny.obj)  # 69 666 triangles, Stanford bunny

mkdir -p "${dest}"

present() { [[ ${force} -eq 0 && -s "${dest}/$(basename "$1")" ]]; }

# apt-get install the package if it is not installed yet (root, or sudo when available).
ensure_package() {
  local package="$1"
  dpkg-query -W -f='${Status}' "${package}" 2>/dev/null | grep -q "install ok installed" && return 0
  local sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  echo "fetch_meshes: installing ${package}"
  export DEBIAN_FRONTEND=noninteractive
  if ! ${sudo} apt-get install -y -qq --no-install-recommends "${package}" >/dev/null 2>&1; then
    ${sudo} apt-get update -qq >/dev/null 2>&1 || true
    ${sudo} apt-get install -y -qq --no-install-recommends "${package}" >/dev/null 2>&1 || return 1
  fi
}

placed=()
missing=()
for f in "${cgal_meshes[@]}"; do present "${f}" || missing+=("${f}"); done
if [[ ${#missing[@]} -gt 0 ]]; then
  if ensure_package libcgal-demo; then
    work="$(mktemp -d)"
    trap 'rm -rf "${work}"' EXIT
    place_from_archive /usr/share/doc/libcgal-dev/data.tar.gz "${work}" "fetch_meshes: warning: " "${missing[@]}"
  else
    echo "fetch_meshes: warning: could not install libcgal-demo; CGAL meshes skipped" >&2
  fi
fi

for f in "${glmark_meshes[@]}"; do
  present "${f}" && continue
  if ensure_package glmark2-data && [[ -f "/${f}" ]]; then
    place "/${f}"
  else
    echo "fetch_meshes: note: glmark2-data's bunny unavailable; skipped" >&2
  fi
done

count=$(find "${dest}" -maxdepth 1 -type f | wc -l)
report_placed "fetch_meshes: placed " 24
echo "fetch_meshes: ${count} meshes in ${dest}"
[[ ${count} -gt 0 ]]
