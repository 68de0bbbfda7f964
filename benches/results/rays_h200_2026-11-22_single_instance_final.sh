#!/bin/bash
S=.dev/solari
$S bench-rays --heightfield 2048 --frames 200 --presets fastest,very-slow --compare-checks --json > $OUT/exp5.jsonl 2>>$OUT/exp5.err
$S bench-rays .dev/scenes/damaged_helmet/DamagedHelmet.gltf --frames 200 --presets medium --compare-checks --json >> $OUT/exp5.jsonl 2>>$OUT/exp5.err
