"""Long work off Blender's main thread. The core releases the GIL and calls progress(fraction)
from its own threads; returning False makes it stop with ifsforge.Cancelled (no bpy here)."""
import threading


class Job:
    """Runs work(progress) -> result on a thread (start) or in place (run)."""

    def __init__(self, work):
        self._work = work
        self._cancel = threading.Event()
        self._thread = None
        self.fraction = 0.0
        self.result = None
        self.error = None

    def progress(self, fraction):
        self.fraction = float(fraction)
        return not self._cancel.is_set()

    def run(self):
        try:
            self.result = self._work(self.progress)
        except Exception as error:  # handed to the main thread, which reports it
            self.error = error
        return self

    def start(self):
        self._thread = threading.Thread(target=self.run, name="ifsforge job", daemon=True)
        self._thread.start()
        return self

    def cancel(self):
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    @property
    def done(self):
        return self._thread is None or not self._thread.is_alive()

    def wait(self, timeout=None):
        if self._thread is not None:
            self._thread.join(timeout)
        return self.done
