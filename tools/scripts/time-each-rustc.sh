#!/usr/bin/env bash
# A RUSTC_WRAPPER that runs each rustc under /usr/bin/time and appends `crate CPU-seconds` (user +
# system) to $RUSTC_TIME_LOG (default: rustc-times.log in the current folder), for the CPU time
# of each unit of a build on a machine other work shares (docs/build-cost.md):
#
#   RUSTC_WRAPPER=$PWD/tools/scripts/time-each-rustc.sh RUSTC_TIME_LOG=$PWD/times.log \
#     cargo build --release --timings -p spectral-quadrature-tools --bin report
#   sort -k2 -n -r times.log | head
name=""
prev=""
kind=""
for a in "$@"; do
  if [ "$prev" = "--crate-name" ]; then name=$a; fi
  if [ "$a" = "build_script_build" ]; then kind=" (build script)"; fi
  prev=$a
done
log="${RUSTC_TIME_LOG:-$PWD/rustc-times.log}"
tmp=$(mktemp)
/usr/bin/time -f '%U %S' -o "$tmp" "$@"
rc=$?
# Cargo's queries of rustc (`-vV`, `--print`) name no crate.
if [ -n "$name" ] && [ -s "$tmp" ]; then
  echo "$name$kind $(awk '{print $1 + $2}' "$tmp")" >>"$log"
fi
rm -f "$tmp"
exit $rc
