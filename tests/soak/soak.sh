#!/usr/bin/env bash
# Soak of fovead under abuse: tests/soak/soak.sh --minutes N [--build DIR] [--out DIR]
# (tests/soak/soak.py says what runs and what is checked). Last line: `lost N`; exit 0 = passed.
exec python3 "$(dirname "${BASH_SOURCE[0]}")/soak.py" "$@"
