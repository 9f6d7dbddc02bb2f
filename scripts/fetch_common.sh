# Functions shared by datasets/fetch_real_data.sh and scripts/fetch_meshes.sh, which source this
# file (it does nothing on its own). The caller sets `dest` (the folder files are copied to) and
# the array `placed` (the names of the files copied there), which these functions extend.

# place FILE: copy FILE into ${dest} and record its name in `placed`.
place() {
  cp "$1" "${dest}/"
  placed+=("$(basename "$1")")
}

# place_from_archive ARCHIVE WORK WARNING PATH...: extract each PATH of the gzipped tar ARCHIVE
# into the folder WORK and place it; a PATH the archive lacks is skipped, with
# "WARNING<PATH> is not in this libcgal-demo version; skipped" on stderr.
place_from_archive() {
  local archive="$1" work="$2" warning="$3" f
  shift 3
  for f in "$@"; do
    if tar -xzf "${archive}" -C "${work}" "${f}" 2>/dev/null; then
      place "${work}/${f}"
    else
      echo "${warning}${f} is not in this libcgal-demo version; skipped" >&2
    fi
  done
}

# report_placed PREFIX WIDTH: a line per placed file, PREFIX, its name padded to WIDTH, its size.
report_placed() {
  local f
  for f in "${placed[@]}"; do
    printf '%s%-*s %10s bytes\n' "$1" "$2" "${f}" "$(stat -c %s "${dest}/${f}")"
  done
}
