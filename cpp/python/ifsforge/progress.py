"""A progress bar for long work: the callback ifsforge's long functions accept."""
import sys
import time


class ProgressBar:
    """Call with a fraction in [0, 1]; draws on stderr when it is a terminal (or when forced).
    Returns True so the work goes on; Ctrl-C cancels through the core."""

    def __init__(self, label, enabled=None, stream=None):
        self.label = label
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.start = time.monotonic()
        self.shown = -1

    def __call__(self, fraction):
        if not self.enabled:
            return True
        percent = int(fraction * 100)
        if percent != self.shown:
            self.shown = percent
            filled = percent * 30 // 100
            elapsed = time.monotonic() - self.start
            self.stream.write(f"\r{self.label} [{'#' * filled}{'.' * (30 - filled)}] {percent:3d}% {elapsed:6.1f}s")
            if percent >= 100:
                self.stream.write("\n")
            self.stream.flush()
        return True
