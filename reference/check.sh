#!/usr/bin/env bash
# Regenerate the reference fixtures in a fresh venv with the pinned wheels and fail if they
# differ numerically from the committed ones. Needs network access to PyPI; fails loudly
# (non-zero) if it cannot install, never skips.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d "${TMPDIR:-/tmp}/tubecast-reference.XXXXXX")"
trap 'rm -rf "$work"' EXIT

die() { echo "reference/check.sh: FAILED: $*" >&2; exit 1; }

python="${PYTHON:-python3}"
command -v "$python" >/dev/null || die "$python not found"
"$python" -m venv "$work/venv" || die "could not create a venv with $python"
if ! "$work/venv/bin/pip" install --quiet --disable-pip-version-check --only-binary=:all: \
        -r "$here/requirements.txt"; then
    die "pip could not install the pinned wheels from reference/requirements.txt (is PyPI reachable?)"
fi

echo "reference/check.sh: regenerating fixtures into $work/fixtures"
"$work/venv/bin/python" "$here/generate.py" --out "$work/fixtures" \
    || die "generate.py failed"
if ! "$work/venv/bin/python" "$here/compare.py" "$here/fixtures" "$work/fixtures"; then
    die "regenerated fixtures differ from the committed ones in reference/fixtures (see above); \
if the change is intended, run: python reference/generate.py (in a venv with reference/requirements.txt) and commit"
fi
echo "reference/check.sh: OK, committed fixtures reproduce"

# Tractography readers (nibabel, trx-python): their own venv, fixtures compared exactly (the
# fixture is what the reference readers read from the committed inputs under readers/).
"$python" -m venv "$work/venv-readers" || die "could not create a venv with $python"
"$work/venv-readers/bin/pip" install --quiet --disable-pip-version-check --only-binary=:all: \
    -r "$here/requirements-readers.txt" || die "pip could not install reference/requirements-readers.txt"
"$work/venv-readers/bin/python" "$here/readers.py" --out "$work/readers" || die "readers.py failed"
cmp "$here/readers/fixture.json" "$work/readers/fixture.json" \
    || die "reference/readers/fixture.json differs from what the pinned readers read (run reference/readers.py)"
echo "reference/check.sh: OK, reader fixtures reproduce"
