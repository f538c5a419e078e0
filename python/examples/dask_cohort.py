"""The book's Dask recipe: one tensorglyph report per participant as one Dask task each, then
the group page.

    python python/examples/dask_cohort.py BIDS_DIR OUT_DIR [--workers N]
    python python/examples/dask_cohort.py BIDS_DIR OUT_DIR --slurm JOBS   (dask-jobqueue)

On one machine it starts a LocalCluster of N worker processes (one thread each: a report
already uses the machine's cores for its figures); with --slurm, dask-jobqueue's SLURMCluster
submits JOBS Slurm jobs of one worker each. A participant whose report fails is printed on
stderr and the others finish; the group page lists everyone. Exit status 0 when every
participant was reported, 1 otherwise. python/tests/test_cohort.py runs it on a LocalCluster
and compares every page with a serial run's."""

import argparse
import os
import sys
from pathlib import Path


def participant(bids_dir: str, out_dir: str, label: str):
    """One participant's report, in a worker process: (label, its error or None)."""
    import tensorglyph as tg

    os.environ.setdefault("XDG_RUNTIME_DIR", "/tmp")
    done = tg.report(bids_dir=bids_dir, out_dir=out_dir, participant_label=[label],
                     reproducible=True)
    return label, done["failed"].get(f"sub-{label}")


def labels(bids_dir: str):
    """The participants' labels, in sorted order (as the participant level takes them)."""
    return sorted(p.name[len("sub-"):] for p in Path(bids_dir).iterdir()
                  if p.is_dir() and p.name.startswith("sub-"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bids_dir")
    parser.add_argument("out_dir")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--slurm", type=int, metavar="JOBS",
                        help="run on Slurm through dask-jobqueue, JOBS jobs of one worker")
    args = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    import tensorglyph as tg

    # --8<-- [start:recipe]
    if args.slurm:
        from dask_jobqueue import SLURMCluster

        cluster = SLURMCluster(cores=2, processes=1, memory="2GB", walltime="00:15:00")
        cluster.scale(jobs=args.slurm)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True)
    with cluster, Client(cluster) as client:
        todo = labels(args.bids_dir)
        futures = client.map(participant, [args.bids_dir] * len(todo),
                             [args.out_dir] * len(todo), todo, pure=False)
        results = client.gather(futures)
    failed = [(label, error) for label, error in results if error]
    for label, error in failed:
        print(f"error: {error}", file=sys.stderr)
    group = tg.group_report(args.bids_dir, args.out_dir)
    # --8<-- [end:recipe]
    print(f"{group['page']}: {group['participants']} participants, {group['maps']} maps; "
          f"{len(group['without_report'])} without a report, "
          f"{len(group['flagged'])} maps flagged")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
