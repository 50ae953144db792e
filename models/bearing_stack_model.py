#!/usr/bin/env python3
"""The bearing stack's axial play computed by a program of its own (kind = "external",
models/bearing_stack_external.toml): the protocol of docs/own-mechanism.md, "An external program".

Poise writes one JSON line per sample, {"sample": 17, "inputs": {"housing": 60.01, ...}}, with
each parameter in the unit its value is written in the model file (mm here); the program answers
one line per sample, {"sample": 17, "outputs": {"gap": 0.52, ...}} in the outputs' declared units,
or {"sample": 17, "failed": "why"}, and flushes after each batch.
"""
import json
import sys

for line in sys.stdin:
    request = json.loads(line)
    x = request["inputs"]
    stack = x["bearing_a"] + x["spacer"] + x["bearing_b"]
    gap = x["housing"] - stack
    answer = {"sample": request["sample"], "outputs": {"gap": gap, "gap_share": 100.0 * gap / x["housing"]}}
    sys.stdout.write(json.dumps(answer) + "\n")
    sys.stdout.flush()
