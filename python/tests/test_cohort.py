"""The book's Dask recipe (python/examples/dask_cohort.py) on a LocalCluster of several workers
over tests/data/bids: every page and figure byte for byte a serial run's (``reproducible=True``),
the broken participant reported while the others finish, the group page listing everyone and
equal to the command line's group level over the same folder."""

import filecmp
import subprocess
import sys

import tensorglyph
from conftest import REPO, require, run_cli

BIDS = REPO / "tests" / "data" / "bids" / "derivatives"
RECIPE = REPO / "python" / "examples" / "dask_cohort.py"


def tree(folder):
    return sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file())


def test_the_dask_recipe_equals_a_serial_run_and_lists_everyone(tmp_path):
    require("dask.distributed")
    serial, parallel = tmp_path / "serial", tmp_path / "dask"
    done = tensorglyph.report(bids_dir=BIDS, out_dir=serial, reproducible=True)
    assert sorted(done["written"]) == ["sub-01", "sub-02", "sub-03", "sub-05"]
    assert list(done["failed"]) == ["sub-04"]

    p = subprocess.run(
        [sys.executable, str(RECIPE), str(BIDS), str(parallel), "--workers", "3"],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 1, p.stderr
    errors = [line for line in p.stderr.splitlines() if line.startswith("error: ")]
    assert len(errors) == 1 and errors[0].startswith("error: sub-04: "), p.stderr
    assert "gzip data is corrupt" in errors[0]
    assert p.stdout.endswith(
        "group.html: 5 participants, 5 maps; 1 without a report, 2 maps flagged\n"
    ), p.stdout

    # The command line's group level over the serial run: then the two folders hold the same
    # files, byte for byte (pages, figures, summaries, and the group page and table).
    run_cli("report", BIDS, serial, "group")
    assert tree(serial) == tree(parallel)
    names = [str(f) for f in tree(serial)]
    assert "sub-04.json" in names and "sub-04.html" not in names
    match, mismatch, errs = filecmp.cmpfiles(serial, parallel, names, shallow=False)
    assert mismatch == [] and errs == [], (mismatch, errs)

    group = tensorglyph.group_report(BIDS, parallel)
    assert group["participants"] == 5 and group["without_report"] == ["sub-04"]
    assert group["page"] == str(parallel / "group.html")
    rows = (parallel / "group.tsv").read_text().splitlines()[1:]
    assert [r.split("\t")[0] for r in rows] == [
        "sub-01", "sub-02", "sub-03", "sub-03", "sub-04", "sub-05",
    ]


def test_group_report_names_a_missing_participant():
    try:
        tensorglyph.group_report(BIDS, "/nonexistent-out", participant_label="99")
    except tensorglyph.Error as e:
        assert "no participant 99" in str(e)
    else:
        raise AssertionError("group_report accepted an unknown participant")
