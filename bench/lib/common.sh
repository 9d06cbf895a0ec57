# shellcheck shell=bash
# Shared by the bench scripts (sourced, not run).

# bench_setup NAME BUILD: sets ROPECAST (BUILD/tools/ropecast, which must exist), WORK (from the environment, or
# a fresh folder under /tmp named after NAME), SIZE and IMAGE (environment or the defaults 256 and 512x512),
# and headless Mesa unless EGL_PLATFORM says otherwise.
bench_setup() {
  local name=$1
  BUILD=$2
  ROPECAST=$BUILD/tools/ropecast
  SIZE=${SIZE:-256}
  IMAGE=${IMAGE:-512x512}
  WORK=${WORK:-$(mktemp -d "/tmp/$name.XXXXXX")}
  mkdir -p "$WORK"
  export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
  [ -x "$ROPECAST" ] || { echo "$name: $ROPECAST not built" >&2; exit 1; }
}

# write_ramp_tf FILE [FROM]: the "linear" preset's ramp over uint8 data (opacity from FROM, default 25.5, up to
# 0.1 at 255), written out so that every renderer reads the very same points.
write_ramp_tf() {
  printf '{"points": [[0, 0.0, 0.0, 0.0, 0.0], [%s, 0.2, 0.1, 0.05, 0.0], [255, 1.0, 0.95, 0.85, 0.1]]}\n' \
    "${2:-25.5}" > "$1"
}

# ct_generator_source: the C++ of convert_bench.sh's generator of CT-like int16 volumes.
ct_generator_source() {
  local here
  here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  # shellcheck disable=SC2016  # a sed address, not a shell expansion
  sed -n '/^cat > "\$scratch\/gen.cpp"/,/^CPP$/p' "$here/convert_bench.sh" | sed '1d;$d'
}

# ct_store DIMS: prints the path of the CT-like int16 store of DIMS (NXxNYxNZ: a smooth field over a ball plus
# noise) in WORK, converting it first when it is not there. CT_GEN names a built generator
# (scripts/device_prepare makes one for machines without a compiler); else it is compiled here.
ct_store() {
  local dims=$1 nx ny nz
  local store="$WORK/ct_${dims}.rcast"
  if [ ! -f "$store" ]; then
    IFS=x read -r nx ny nz <<<"$dims"
    local gen=${CT_GEN:-}
    if [ -z "$gen" ]; then
      ct_generator_source >"$WORK/gen.cpp"
      c++ -O2 -o "$WORK/gen" "$WORK/gen.cpp" >&2 || return 1
      gen="$WORK/gen"
    fi
    local raw="$WORK/ct_${dims}_int16.raw"
    "$gen" "$nx" "$ny" "$nz" "$raw" >&2 || return 1
    "$ROPECAST" convert "$raw" -o "$store" --quiet >&2 || return 1
    rm -f "$raw"
  fi
  echo "$store"
}

# cache_state: drops the page cache when run as root and prints "cold", else prints "warm".
cache_state() {
  if [ "$(id -u)" = 0 ] && sync && echo 3 >/proc/sys/vm/drop_caches 2>/dev/null; then echo cold; else echo warm; fi
}

# render_run NAME STORE ARGS...: one `ropecast render STORE ARGS...` with --stats WORK/NAME.jsonl, after
# cache_state; its wall seconds in WORK/NAME.s and the cache state in WORK/NAME.cache (read back by
# bench/lib/render_runs.py).
render_run() {
  local name=$1 store=$2
  shift 2
  local cache t0 t1
  cache=$(cache_state)
  t0=$(date +%s.%N)
  "$ROPECAST" render "$store" --stats "$WORK/$name.jsonl" -o "$WORK/$name.png" "$@" >/dev/null 2>"$WORK/$name.err" ||
    { cat "$WORK/$name.err" >&2; return 1; }
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f\n", b - a }' >"$WORK/$name.s"
  echo "$cache" >"$WORK/$name.cache"
}
