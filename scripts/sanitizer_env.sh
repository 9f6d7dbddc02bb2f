# Sourced by scripts/test.sh and scripts/fuzz.sh: what every sanitized run shares.
# The sanitizer builds (the asan and fuzz presets) are clang 15's, whose runtime names a
# report's frames by file and line only through llvm-symbolizer; Debian's llvm-15 installs it
# in /usr/lib/llvm-15/bin, off PATH (without it a stack is module+offset, as in
# "(fuzz_mesh+0xa6a62)"). A caller's own ASAN_SYMBOLIZER_PATH is kept.
if [[ -z "${ASAN_SYMBOLIZER_PATH:-}" && -x /usr/lib/llvm-15/bin/llvm-symbolizer ]]; then
  export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-15/bin/llvm-symbolizer
fi
