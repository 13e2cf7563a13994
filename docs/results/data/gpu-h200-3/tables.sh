#!/usr/bin/env bash
# Makes update-times.txt and kernel-times.txt from the calls' files (run from this folder).
s=../../../../scripts
for c in 1 2; do for g in 9c 16c; do
    $s/update-times.py call$c-metrics-ippo-$g-2p.jsonl "call $c $g"
done; done > update-times.txt
for c in 1 2; do for g in 9c 16c; do
    $s/cubecl-kernel-times.py call$c-cubecl-ippo-$g-2p.log.xz --top 6
    $s/cubecl-kernel-times.py call$c-cubecl-ippo-$g-2p.log.xz --family ReduceKernel --top 8
    echo
done; done > kernel-times.txt
