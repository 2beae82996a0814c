#!/usr/bin/env bash
# Runs the Khronos glTF validator (npm package `gltf-validator`, pinned) on `.glb` files and
# fails when any has an error. Needs node and npm (registry access for the first install).
# Usage: crates/lab/peers/gltf_validate.sh FILE.glb [FILE.glb ...]
set -euo pipefail
dir="${GLTF_VALIDATOR_DIR:-/tmp/gltf-validator}"
if [ ! -d "$dir/node_modules/gltf-validator" ]; then
  mkdir -p "$dir" && (cd "$dir" && npm install --silent gltf-validator@2.0.0-dev.3.10 >/dev/null)
fi
NODE_PATH="$dir/node_modules" node - "$@" <<'JS'
const v = require('gltf-validator');
const fs = require('fs');
(async () => {
  let bad = 0;
  for (const f of process.argv.slice(2)) {
    const r = await v.validateBytes(new Uint8Array(fs.readFileSync(f)));
    const i = r.issues;
    console.log(`${f}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
    for (const m of i.messages) console.log(`  ${m.severity === 0 ? 'error' : 'note'} ${m.code}: ${m.message} ${m.pointer || ''}`);
    bad += i.numErrors;
  }
  process.exit(bad > 0 ? 1 : 0);
})();
JS
