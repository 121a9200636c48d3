"""SofaRuntime: importPlugin (every component is built in: accepted, nothing to load) and Timer
(SOFA's AdvancedTimer API over wall-clock time: begin/end of named timers, the records of the last
end)."""
from __future__ import annotations

import time


def importPlugin(name):  # noqa: N802 - SofaPython3's name
    """Accepted for any SOFA plugin name: penalty's components need no plugin."""
    return True


def unloadModules():  # noqa: N802
    return None


class Timer:
    """SofaRuntime.Timer (SOFA's AdvancedTimer): named timers; getRecords(name) gives the last
    interval of a timer: {"total_time": ms, "start_time": ms, "end_time": ms}. SOFA's own inner
    records (its visitors' names) are not reproduced."""

    _enabled: dict = {}
    _started: dict = {}
    _records: dict = {}
    _interval: dict = {}

    @classmethod
    def isEnabled(cls, name):  # noqa: N802
        return bool(cls._enabled.get(name, False))

    @classmethod
    def setEnabled(cls, name, flag):  # noqa: N802
        cls._enabled[name] = bool(flag)

    @classmethod
    def begin(cls, name):
        cls._started[name] = time.perf_counter()

    @classmethod
    def stepBegin(cls, name):  # noqa: N802
        cls.begin(name)

    @classmethod
    def end(cls, name, *_args):
        start = cls._started.pop(name, None)
        if start is None:
            return ""
        now = time.perf_counter()
        cls._records[name] = {"total_time": (now - start) * 1e3, "start_time": start * 1e3, "end_time": now * 1e3}
        return ""

    @classmethod
    def stepEnd(cls, name):  # noqa: N802
        cls.end(name)

    @classmethod
    def getRecords(cls, name):  # noqa: N802
        return dict(cls._records.get(name, {}))

    @classmethod
    def clear(cls):
        cls._records.clear()
        cls._started.clear()

    @classmethod
    def setInterval(cls, name, interval):  # noqa: N802
        cls._interval[name] = int(interval)

    @classmethod
    def getInterval(cls, name):  # noqa: N802
        return cls._interval.get(name, 0)

    @classmethod
    def setOutputType(cls, name, kind):  # noqa: N802
        return None
