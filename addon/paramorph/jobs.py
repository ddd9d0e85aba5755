"""Runs one native call off Blender's main thread: the call releases the GIL,
reports progress through a callback, and stops when asked (the callback
returns False and the native side raises `Cancelled`). Blender data is only
read before the job starts and written after it ends, on the main thread, so
a cancelled or failed job leaves the scene as it was."""
import threading
import time

_running = set()  # jobs whose thread is alive (started with start())


def running():
    """The jobs running in threads now (the panel shows them with a Cancel button)."""
    return [job for job in list(_running) if not job.done()]


def cancel_all():
    for job in running():
        job.cancel()


class NativeJob:
    def __init__(self, function, *args, **kwargs):
        self._function = function
        self._args = args
        self._kwargs = kwargs
        self._cancel = threading.Event()
        self._thread = None
        self.fraction = 0.0
        self.stage = ""
        self.result = None
        self.error = None
        # time.monotonic() of the cancel request and of the call's end (None
        # before): how long a cancel took, for the window tests and benchmarks.
        self.cancelled_at = self.ended_at = None

    def _progress(self, fraction, stage):
        self.fraction = float(fraction)
        self.stage = stage
        return not self._cancel.is_set()

    def _run(self):
        try:
            self.result = self._function(*self._args, progress=self._progress, **self._kwargs)
        except BaseException as error:  # handed to the main thread, reported there
            self.error = error
        finally:
            self.ended_at = time.monotonic()
            _running.discard(self)

    def start(self):
        self._thread = threading.Thread(target=self._run, name="paramorph-native", daemon=True)
        _running.add(self)
        self._thread.start()
        return self

    def run(self):
        """Runs on the calling thread (background mode, redo, scripts)."""
        self._run()
        return self

    def cancel(self):
        if self.cancelled_at is None:
            self.cancelled_at = time.monotonic()
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def done(self):
        return self._thread is None or not self._thread.is_alive()

    def wait(self, timeout=None):
        if self._thread is not None:
            self._thread.join(timeout)
        return self.done()
