"""What the worker processes of a sweep's LocalCluster are told (imported only with Dask)."""

from __future__ import annotations

import signal
import threading

from distributed import WorkerPlugin


class IgnoreInterrupt(WorkerPlugin):
    """Ctrl-C at a terminal reaches every process of its group: the workers leave it to the
    sweep, which stops them as it stops (a worker that took it would die with a traceback).
    Workers the nanny starts again get the plugin too."""

    name = "schemalog-ignore-interrupt"

    def setup(self, worker) -> None:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)
