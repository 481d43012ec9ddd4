#!/usr/bin/env bash
# Build time and peak memory of bridge models vs size, one process per model (the
# "Big models" table in docs/performance.md). Each row runs the default scenario with its model
# replaced, for 1 ms of simulated time: the time and memory are the model's build and the
# solver's set-up, plus a run's fixed cost (the default FE 50 row shows it).
#
#   tools/model_build_table.sh [BINARY] > build_table.csv
#
# Needs GNU time (/usr/bin/time, Debian package `time`).
set -euo pipefail
bin=${1:-target/release/bridgetwin}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" scenario show > "$work/default.toml"
models=(
  'kind = "finite_element", elements = 50'
  'kind = "finite_element", elements = 500'
  'kind = "finite_element", elements = 1000'
  'kind = "finite_element", elements = 5000'
  'kind = "finite_element", elements = 20000'
  'kind = "finite_element", elements = 100000'
  'kind = "modal", modes = 20'
  'kind = "modal", modes = 100'
  'kind = "modal", modes = 500, elements = 2000'
  'kind = "modal", modes = 1000'
  'kind = "lumped_mass", nodes = 100'
  'kind = "lumped_mass", nodes = 500'
  'kind = "lumped_mass", nodes = 1000'
  'kind = "lumped_mass", nodes = 2000'
)
echo "model,build_and_setup_s,peak_rss_mib"
for model in "${models[@]}"; do
  sed "s/^model = { kind = \"finite_element\", elements = 50 }/model = { $model }/" \
    "$work/default.toml" > "$work/model.toml"
  grep -qF "$model" "$work/model.toml" || { echo "default scenario changed its model line" >&2; exit 1; }
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$bin" simulate "$work/model.toml" \
    --duration-s 0.001 --out "$work/run.mcap" --force --quiet 2> /dev/null
  read -r seconds kib < "$work/time.txt"
  echo "\"$model\",$seconds,$((kib / 1024))"
done
