#!/usr/bin/env bash
# Golden-image regression renders (tests/regression/): every case must match its golden image.
exec bash "$(dirname "$0")/../regression/run.sh" check "$1"
