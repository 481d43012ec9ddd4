#!/usr/bin/env bash
# Seeds the fuzz corpora: every scenario of the repository for the parser; small runs
# (both layouts, a split part, a killed run's .partial) for the MCAP readers. The corpora
# and what the fuzzer finds stay out of git (tests/fuzz/.gitignore).
# Usage, from the repository root, after `cargo build --release`:
#   tests/fuzz/seed_corpus.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
bt=./target/release/bridgetwin
corpus=tests/fuzz/corpus
mkdir -p "$corpus/scenario_parser" "$corpus/mcap_readers"
cp src/scenario/default.toml "$corpus/scenario_parser/default.toml"
for f in examples/*.toml examples/sweeps/*.toml; do
  cp "$f" "$corpus/scenario_parser/$(basename "$f")"
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Short runs keep the inputs small (tens of kB): the fuzzer mutates them faster.
$bt simulate --quiet --duration-s 0.2 --out "$corpus/mcap_readers/default.mcap" --force
$bt scenario show | sed 's/layout = "sample"/layout = "block"/' > "$tmp/block.toml"
$bt simulate --quiet "$tmp/block.toml" --duration-s 0.2 --out "$corpus/mcap_readers/block.mcap" --force
$bt scenario show | sed 's/^\[output\]/[output]\nsplit_every_s = 1.0/' > "$tmp/split.toml"
$bt simulate --quiet "$tmp/split.toml" --duration-s 1.2 --out "$tmp/split.mcap" --force
cp "$tmp"/split-0001.mcap "$corpus/mcap_readers/split-0001.mcap"
head -c 20000 "$corpus/mcap_readers/default.mcap" > "$corpus/mcap_readers/cut.mcap"
ls -la "$corpus"/*
