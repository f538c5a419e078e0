"""The renderer lives for the process: several threads render at once, and many renders in one
process do not grow its memory."""

import threading

import numpy as np

import tensorglyph as tg
from test_truth import random_tensors


def rss_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return None


def test_four_threads_render_at_once_and_get_what_one_thread_gets():
    jobs = [
        dict(demo="grid:8", size=(160, 120)),
        dict(data=random_tensors((6, 6, 4)), slice="all", size=(150, 100)),
        dict(demo="grid:5", size=(128, 96), glyph="superquadric", outlines=True),
        dict(demo="grid:6", size=(140, 100), method="sigg", glyph="cylinder"),
    ]
    alone = [tg.render(**j)._rgba for j in jobs]
    results = [None] * 8
    errors = []

    def work(k):
        try:
            results[k] = tg.render(**jobs[k % 4])._rgba
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for k, r in enumerate(results):
        assert np.array_equal(r, alone[k % 4]), k


def test_two_hundred_renders_do_not_grow_memory():
    t = random_tensors((8, 8, 6), seed=4)
    for _ in range(20):
        tg.render(t, size=(200, 150), slice="all")
    before = rss_bytes()
    for k in range(200):
        image = tg.render(t, size=(200, 150), slice="all", azimuth=float(k))
        assert image.array.shape == (150, 200, 3)
    after = rss_bytes()
    grown = after - before
    print(f"RSS after 20 renders {before / 2**20:.1f} MiB, after 200 more {after / 2**20:.1f} MiB "
          f"({grown / 2**20:+.1f} MiB)")
    assert grown < 32 * 2**20, f"RSS grew {grown / 2**20:.1f} MiB over 200 renders"
