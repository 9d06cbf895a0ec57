#!/usr/bin/env bash
# The project's golden images (tests/regression/suite.json) through `ropecast regress`: every case must match.
# With ROPECAST_REGRESSION_OUT=DIR the HTML report (renders, goldens, difference images) is kept there.
# Usage: bash regression.sh /path/to/ropecast
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
report=()
[ -n "${ROPECAST_REGRESSION_OUT:-}" ] && report=(--report "$ROPECAST_REGRESSION_OUT")
exec "$1" regress "$here/../regression/suite.json" "${report[@]}"
