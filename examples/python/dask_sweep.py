"""A parameter sweep of the double pendulum spread over a Dask cluster.

Each task rebuilds the model from its .dyad text on the worker (a model is
cheap to load: microseconds), simulates one set of values, and sends back
the result (numpy arrays) and the worker that ran it.

    pip install ./crates/multibody-py "dask[distributed]"
    python examples/python/dask_sweep.py                      # a local cluster of 2 worker processes
    python examples/python/dask_sweep.py tcp://scheduler:8786 # a real cluster

On a real cluster, every worker needs the package installed (the same
`pip install` on each machine, or in the workers' image); the scheduler's
address is what `dask scheduler` prints when it starts.
"""

import sys
from pathlib import Path

import multibody

MODEL = Path(__file__).resolve().parent.parent / "double_pendulum.dyad"


def simulate_on_worker(text, params):
    """Runs on a worker: load the model from its text, simulate one set."""
    from distributed import get_worker

    import multibody

    result = multibody.loads(text, file="double_pendulum.dyad").simulate(params=params)
    return get_worker().address, result


def sweep(client, lengths):
    """The results of one run per length of the first link, in order, and
    the workers that ran them."""
    text = MODEL.read_text()
    futures = client.map(simulate_on_worker, [text] * len(lengths), [{"link1.length": x} for x in lengths], pure=False)
    done = client.gather(futures)
    return [result for _, result in done], [worker for worker, _ in done]


def main():
    from distributed import Client, LocalCluster

    if len(sys.argv) > 1:
        client = Client(sys.argv[1])
    else:
        client = Client(LocalCluster(n_workers=2, threads_per_worker=1, processes=True))
    lengths = [0.5 + 0.05 * k for k in range(20)]
    with client:
        results, workers = sweep(client, lengths)
    for length, result in zip(lengths[:3], results):
        print(f"link1.length = {length:.2f}: link2.joint.phi(end) = {result['link2.joint.phi'][-1]:+.6f}")
    print(f"{len(results)} runs on {len(set(workers))} workers: {sorted(set(workers))}")


if __name__ == "__main__":
    main()
