"""Scale-out on Dask distributed: the core's jobs run on a cluster and merge exactly here.

The core cuts a render into jobs whose results merge exactly (address prefixes for point
recursive rendering, (seed, job) random streams for random iteration, integer sums per voxel
or pixel). This module hands ranges of those jobs to the workers of a `distributed.Client`
(each returns compact bytes) and lets the core merge them, so the volume or the image is the
same bytes as a single-process render with the same seed and options. Dask re-runs the task
of a worker that dies; the result does not change.

    client = ifsforge.distributed.connect("tcp://10.0.0.1:8786")   # or cluster="local:2"
    volume = ifsforge.distributed.render_volume(system, "prr", resolution=1024, client=client)
    ifsforge.distributed.render_volume_to_vdb("p.vdb", system, "prr", resolution=2048, client=client)

Every worker needs the same ifsforge build (connect() checks it and names a worker without it).
"""
import contextlib
import os

import ifsforge
from ifsforge import _core

#: Seconds to reach a scheduler before giving up (so an unreachable one fails promptly).
CONNECT_TIMEOUT = 5.0
#: Seconds a local cluster's worker processes may take to start and register.
LOCAL_START_TIMEOUT = 60.0
#: Seconds a job may wait with no worker connected, or with a scheduler that does not answer,
#: before it fails (IFSFORGE_CLUSTER_TIMEOUT overrides): Dask itself would wait for a worker forever.
NO_WORKER_TIMEOUT = 60.0
#: Tasks per worker thread a volume is cut into (load balance against per-task overhead).
TASKS_PER_THREAD = 4
#: Tasks per worker thread an image is cut into: fewer than for volumes, because each task of a
#: chaos image fills and encodes counters for every pixel, a cost per task that several times
#: its jobs' own work would not repay.
IMAGE_TASKS_PER_THREAD = 2
#: Tasks per worker thread an animation's frames are cut into: several frames per task, as the
#: driver's cost per task is a sizeable part of one small frame's render.
FRAME_TASKS_PER_THREAD = 8
#: Dask settings for the worker processes of a local cluster (dask-worker reads the same from
#: DASK_DISTRIBUTED__... variables, see docs/scale-out.md). Dask's statistical profiler samples a
#: busy worker's stack for a dashboard nobody opens, and its event-loop tick and memory and system
#: monitors wake an idle worker many times a second: CPU the render's workers need.
QUIET_WORKERS = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
}

# Evaluated on each worker by the builtin eval (so the probe itself needs no ifsforge there):
# the digest of the compiled core the worker imports.
_BUILD_PROBE = ("__import__('hashlib').sha256(open(__import__('importlib').import_module('ifsforge._core')"
                ".__file__, 'rb').read()).hexdigest()")


class ClusterError(ifsforge.Error, ConnectionError):
    """The cluster cannot run the jobs: no scheduler, no worker, a worker without ifsforge."""


def build_digest():
    """The digest of this process's compiled core (what every worker must match)."""
    import hashlib  # here: loading OpenSSL slows every command's start, and only clusters need it
    with open(_core.__file__, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def parse_cluster(text):
    """'local' or 'local:N' -> N worker processes (default 2); InputError otherwise."""
    name, _, count = text.partition(":")
    if name != "local":
        raise ifsforge.InputError(f"--cluster expects local or local:N, got '{text}'")
    if not count:
        return 2
    if not count.isdigit() or not 1 <= int(count) <= 256:
        raise ifsforge.InputError(f"--cluster local:N expects N in 1..256, got '{text}'")
    return int(count)


def _distributed():
    try:
        import distributed
    except ImportError:
        raise ClusterError("Dask distributed is not installed (Debian: apt-get install python3-distributed)") from None
    return distributed


def check_workers(client):
    """Every worker imports the same ifsforge build as this process; ClusterError names one that does not."""
    expected = build_digest()
    answers = client.run(eval, _BUILD_PROBE, on_error="return")
    if not answers:
        raise ClusterError(f"the Dask scheduler at {client.scheduler.address} has no worker")
    for worker, answer in sorted(answers.items()):
        if isinstance(answer, BaseException):
            raise ClusterError(f"Dask worker {worker} cannot import ifsforge ({type(answer).__name__}: {answer}); "
                               "install the same ifsforge build on every worker")
        if answer != expected:
            raise ClusterError(f"Dask worker {worker} runs another ifsforge build (core {answer[:12]}, "
                               f"here {expected[:12]}): install the same build on every worker")


def local_cluster(workers):
    """A LocalCluster of `workers` processes of one thread each on this machine (QUIET_WORKERS)."""
    distributed = _distributed()
    import dask  # installed with distributed
    with dask.config.set(QUIET_WORKERS):  # the worker processes take the config they start with
        return distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                        dashboard_address=None, silence_logs=50)


@contextlib.contextmanager
def connect(scheduler=None, cluster=None, timeout=CONNECT_TIMEOUT):
    """A checked `distributed.Client`: to the scheduler at `scheduler` ('tcp://HOST:PORT'), or
    to a LocalCluster of `cluster` ('local[:N]') worker processes started here and stopped on
    exit. ClusterError (within `timeout` seconds) when the scheduler cannot be reached."""
    if (scheduler is None) == (cluster is None):
        raise ifsforge.InputError("give either a scheduler address (--scheduler) or a local cluster (--cluster)")
    workers = parse_cluster(cluster) if cluster is not None else 0
    distributed = _distributed()
    with contextlib.ExitStack() as stack:
        if cluster is not None:
            local = stack.enter_context(local_cluster(workers))
            address = local.scheduler_address
        else:
            address = scheduler
        try:
            client = distributed.Client(address, timeout=timeout, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as error:
            raise ClusterError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s: {error}") from None
        stack.enter_context(client)
        if workers:  # a local cluster's workers may still be registering (a loaded machine)
            try:
                client.wait_for_workers(workers, timeout=LOCAL_START_TIMEOUT)
            except (OSError, TimeoutError) as error:
                raise ClusterError(f"the local Dask cluster's {workers} workers did not start within "
                                   f"{LOCAL_START_TIMEOUT:g} s: {error}") from None
        check_workers(client)
        yield client


@contextlib.contextmanager
def client_from_args(args):
    """The client the CLI options --scheduler / --cluster ask for, or None without them."""
    if not getattr(args, "scheduler", None) and not getattr(args, "cluster", None):
        yield None
        return
    with connect(scheduler=args.scheduler, cluster=args.cluster) as client:
        yield client


def add_cluster_arguments(parser):
    """--scheduler / --cluster for a CLI command whose work can run on a Dask cluster."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                       help="run the jobs on this Dask scheduler's workers (the same bytes as a local run)")
    group.add_argument("--cluster", metavar="local[:N]",
                       help="run the jobs on N Dask worker processes started on this machine (default 2)")


#: CLI option names that say where the work runs, never what it makes (kept out of file metadata).
CLUSTER_OPTIONS = ("scheduler", "cluster")


def _threads(client):
    return max(1, sum(client.nthreads().values()))


def _runner(client, task, system_json, algorithm, options, tasks_per_thread=TASKS_PER_THREAD):
    """distribute(first, last, depth=0): the jobs cut into ranges, tasks_per_thread tasks per
    worker thread, results in range order. depth: the fixed depth a point-recursive image fell
    back to (its pieces ran past their node budget), which the tasks run at too."""
    def distribute(first, last, depth=0):
        count = max(1, min(last - first, tasks_per_thread * _threads(client)))
        cuts = [first + (last - first) * k // count for k in range(count + 1)]
        jobs = dict(options, depth=depth) if depth else options
        futures = [client.submit(task, system_json, algorithm, jobs, a, b, pure=False)
                   for a, b in zip(cuts, cuts[1:]) if b > a]
        try:
            return gather(client, futures)
        except ifsforge.Error:  # raised by the core on a worker: as it would be here
            raise
        except Exception as error:  # lost connection, a task whose workers kept dying (KilledWorker), ...
            raise ClusterError(f"the cluster failed: {type(error).__name__}: {error}") from None
        finally:
            for future in futures:
                future.release()
    return distribute


def no_worker_timeout():
    try:
        return float(os.environ.get("IFSFORGE_CLUSTER_TIMEOUT", NO_WORKER_TIMEOUT))
    except ValueError:
        raise ifsforge.InputError("IFSFORGE_CLUSTER_TIMEOUT expects seconds, got "
                                  f"'{os.environ['IFSFORGE_CLUSTER_TIMEOUT']}'") from None


def gather(client, futures):
    """client.gather(futures), except that a cluster left without workers, or a scheduler that
    stops answering, fails after no_worker_timeout() seconds with ClusterError naming the
    scheduler (Dask would wait for a worker to join forever)."""
    import threading
    import time
    finished, remaining, lock = threading.Event(), [len(futures)], threading.Lock()

    def one_done(_):
        with lock:
            remaining[0] -= 1
            if remaining[0] == 0:
                finished.set()
    for future in futures:
        future.add_done_callback(one_done)
    limit, alone_since = no_worker_timeout(), None
    while futures and not finished.wait(1.0):
        try:
            workers = len(client.nthreads()) if client.status == "running" else 0
        except (OSError, TimeoutError):
            workers = 0
        if workers:
            alone_since = None
            continue
        alone_since = alone_since or time.monotonic()
        if time.monotonic() - alone_since > limit:
            raise ClusterError(f"the Dask scheduler at {client.scheduler.address} has had no worker (or has not "
                               f"answered) for {limit:g} s; the job was abandoned (IFSFORGE_CLUSTER_TIMEOUT)")
    return client.gather(futures)  # the results, or the first failed task's error


def _volume_task(system_json, algorithm, options, first, last):
    return _core.run_volume_jobs(_core.parse_json(system_json), algorithm, options, first, last)


def _render_task(system_json, algorithm, options, first, last):
    return _core.run_render_jobs(_core.parse_json(system_json), algorithm, options, first, last)


def _worker_options(options):
    # One core per task: Dask runs as many tasks at once as a worker has threads.
    return dict(options, threads=1)


def render_volume(system, algorithm="prr", client=None, progress=None, **options):
    """ifsforge.render_volume with its jobs on `client`'s workers (prr, ria); the same volume.
    Without a client, the local render."""
    if client is None:
        return ifsforge.render_volume(system, algorithm, progress=progress, **options)
    run = _runner(client, _volume_task, ifsforge.to_json(system), algorithm, _worker_options(options))
    return _core.render_volume_distributed(system, algorithm, options, run, progress)


def render_volume_to_vdb(path, system, algorithm="prr", client=None, progress=None, **options):
    """ifsforge.render_volume_to_vdb with its jobs on `client`'s workers (prr, ria): the same file,
    merged here a band at a time (prr). Without a client, the local render."""
    if client is None:
        return ifsforge.render_volume_to_vdb(path, system, algorithm, progress=progress, **options)
    vdb_fields = set(dir(ifsforge.VdbWriteOptions())) - {"threads"}  # the render's (a worker's: one)
    jobs = {k: v for k, v in options.items() if k not in vdb_fields}
    run = _runner(client, _volume_task, ifsforge.to_json(system), algorithm, _worker_options(jobs))
    return ifsforge.render_volume_to_vdb(path, system, algorithm, distribute=run, progress=progress, **options)


def render(system, algorithm="chaos", client=None, progress=None, **options):
    """ifsforge.render with its jobs on `client`'s workers (chaos, prr); the same raster.
    Without a client, the local render."""
    if client is None:
        return ifsforge.render(system, algorithm, progress=progress, **options)
    run = _runner(client, _render_task, ifsforge.to_json(system), algorithm, _worker_options(options),
                  IMAGE_TASKS_PER_THREAD)
    return _core.render_distributed(system, algorithm, options, run, progress)


def _frames_task(frames, algorithm, options, mode):
    sizes = []
    for system_json, path in frames:
        raster = ifsforge.render(_core.parse_json(system_json), algorithm, **options)
        ifsforge.write_png(path, raster.to_image(mode))  # atomic: a reader never sees half a frame
        sizes.append(os.path.getsize(path))
    return sizes


def render_frames(client, frames, algorithm, mode, progress=None, **options):
    """Renders each (system, path) of `frames` with ifsforge.render and writes its PNG (`mode`)
    on a worker, a few consecutive frames per task (FRAME_TASKS_PER_THREAD): `path` must be on
    storage every worker shares. The files are the bytes a local render writes. Returns the
    bytes written per frame."""
    frames = [(ifsforge.to_json(system), os.path.abspath(path)) for system, path in frames]
    count = max(1, min(len(frames), FRAME_TASKS_PER_THREAD * _threads(client)))
    cuts = [len(frames) * k // count for k in range(count + 1)]
    tasks = [client.submit(_frames_task, frames[a:b], algorithm, _worker_options(options), mode, pure=False)
             for a, b in zip(cuts, cuts[1:]) if b > a]
    try:
        sizes = []
        for task in tasks:
            sizes.extend(gather(client, [task])[0])
            if progress is not None and progress(len(sizes) / len(frames)) is False:
                raise ifsforge.Cancelled("cancelled")
        return sizes
    except ifsforge.Error:
        raise
    except Exception as error:
        raise ClusterError(f"the cluster failed: {type(error).__name__}: {error}") from None
    finally:
        client.cancel(tasks)
