"""bench/serial_windows.py: the main thread's samples in windows where no other thread has one."""
import importlib.util
from pathlib import Path

_PATH = Path(__file__).resolve().parents[2] / "bench" / "serial_windows.py"
_spec = importlib.util.spec_from_file_location("serial_windows", _PATH)
serial_windows = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(serial_windows)


def test_only_windows_without_another_threads_sample_count():
    # main thread 10, worker 12; 1 ms windows from t = 100.0 s
    rows = [
        (10, 100.0000, "detect"),  # window 0: the worker runs too
        (12, 100.0004, "fem"),
        (10, 100.0012, "sweep"),  # window 1: main alone
        (10, 100.0017, "sweep"),
        (10, 100.0025, "build"),  # window 2: main alone
        (12, 100.0031, "fem"),  # window 3: worker alone
        (10, 100.0049, "solve"),  # window 4: both
        (12, 100.0041, "fem"),
    ]
    main_tid, serial = serial_windows.serial_samples(rows, 0.001)
    assert main_tid == 10
    assert dict(serial) == {"sweep": 2, "build": 1}


def test_a_wider_window_joins_the_samples_of_both_threads():
    rows = [(3, 5.0, "a"), (3, 5.0015, "b"), (7, 5.0019, "c"), (3, 5.0031, "d")]
    assert dict(serial_windows.serial_samples(rows, 0.001)[1]) == {"a": 1, "d": 1}
    # 2 ms windows: [5.000, 5.002) holds the worker's sample, [5.002, 5.004) does not
    assert dict(serial_windows.serial_samples(rows, 0.002)[1]) == {"d": 1}
