#!/usr/bin/python3
"""The two .npy maps as one text record, in the order they were measured (no value changed).

Each .npy is an array indexed by encoder count (8192 a turn) whose unvisited entries hold 0.0
placeholders (SOURCE): c_16 was visited at 0, 16, ..., 8176 (forward), e_16r at 8191, 8175,
..., 15 (backward, the next day). This writes map.csv: one row per visited entry, forward
sweep then backward sweep, with the columns `count` (the encoder count) and `Iq_A` (the
holding current as the file holds it), and no time column (the script held each point about
3 s; the map is quasi-static). Poise reads it with
    --column angle=count --unit angle="1/8192 rev" --column current=Iq_A
"""
import os

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
forward = np.load(os.path.join(here, "cogging_measure_final_c_16.npy"))
backward = np.load(os.path.join(here, "cogging_measure_final_e_16r.npy"))
rows = [(i, forward[i]) for i in range(0, 8192, 16)] + [(8191 - i, backward[8191 - i]) for i in range(0, 8192, 16)]
with open(os.path.join(here, "map.csv"), "w", encoding="utf-8") as f:
    f.write("# gchenfc/ODrive coggingmap_0: c_16 (forward) then e_16r (backward), as measured; see SOURCE\n")
    f.write("count,Iq_A\n")
    for count, current in rows:
        f.write(f"{count},{current!r}\n")
