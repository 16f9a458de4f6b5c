"""`--cpu-durations=N`: the N tests that used the most CPU (the worker's own threads plus the
processes it waited for: commands, Blender), setup and call together. On a busy machine a test's
wall time says more about its neighbours than about the test; its CPU seconds do not."""
import resource

import pytest


def pytest_addoption(parser):
    parser.addoption("--cpu-durations", type=int, default=None, metavar="N",
                     help="show the N tests that used the most CPU seconds (0 for all)")


def cpu_seconds():
    return sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                  resource.getrusage(resource.RUSAGE_CHILDREN)))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    item.cpu_start = cpu_seconds()
    yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    yield
    # Kept in the report, which pytest-xdist's workers send to the process that prints.
    item.user_properties.append(("cpu_seconds", cpu_seconds() - item.cpu_start))


def pytest_terminal_summary(terminalreporter, config):
    count = config.getoption("--cpu-durations")
    if count is None:
        return
    used = [(dict(r.user_properties).get("cpu_seconds"), r.nodeid)
            for kind in ("passed", "failed") for r in terminalreporter.stats.get(kind, []) if r.when == "call"]
    used = sorted(((s, n) for s, n in used if s is not None), reverse=True)
    terminalreporter.write_sep("=", f"CPU seconds: {sum(s for s, _ in used):.1f} in {len(used)} tests")
    for seconds, nodeid in used[:count or None]:
        terminalreporter.write_line(f"{seconds:8.2f}  {nodeid}")
