"""Progress reporting: a tqdm bar with ETA on a terminal, plain log lines otherwise
(Snakemake logs): the first ``first_line_s`` seconds after the start (so that a run shows its
rate and ETA at once), then at most one line per ``log_every_s`` seconds."""

import sys
import time


class Progress:
    def __init__(self, total: float, desc: str, unit: str = "t", log_every_s: float = 30.0,
                 stream=None, initial: float = 0.0, first_line_s: float = 2.0) -> None:
        self.total, self.desc, self.unit = float(total), desc, unit
        self.stream = stream or sys.stderr
        self.value = float(initial)
        self._t0 = time.perf_counter()
        self._v0 = float(initial)
        self._next_log = self._t0 + first_line_s
        self.log_every_s = log_every_s
        self._bar = None
        if hasattr(self.stream, "isatty") and self.stream.isatty():
            from tqdm import tqdm

            self._bar = tqdm(total=self.total, initial=self.value, desc=desc, unit=unit,
                             file=self.stream, dynamic_ncols=True)

    def update_to(self, value: float, info: str = "") -> None:
        delta, self.value = value - self.value, float(value)
        if self._bar is not None:
            self._bar.update(delta)
            if info:
                self._bar.set_postfix_str(info, refresh=False)
            return
        now = time.perf_counter()
        if now >= self._next_log:
            self._next_log = now + self.log_every_s
            self.stream.write(self._line(now, info) + "\n")
            self.stream.flush()

    def _line(self, now: float, info: str) -> str:
        elapsed = now - self._t0
        done = self.value - self._v0
        rate = done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.value) / rate if rate > 0 else float("inf")
        frac = 100.0 * self.value / self.total if self.total else 100.0
        return (f"[{self.desc}] {self.value:.6g}/{self.total:.6g} {self.unit} ({frac:5.1f} %) "
                f"elapsed {elapsed:7.1f} s, eta {eta:7.1f} s {info}").rstrip()

    def close(self, info: str = "done") -> None:
        if self._bar is not None:
            self._bar.close()
        else:
            self.stream.write(self._line(time.perf_counter(), info) + "\n")
            self.stream.flush()
