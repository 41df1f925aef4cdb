"""Runs `nbrdf bake --progress=json` as a child process and follows its JSON lines.

No bpy here on purpose: the modal operator, the blocking execute() and the headless tests
all drive this one class, so what the tests exercise is what runs behind the button.
Background mode (blender -b) never ticks modal timers, hence the synchronous poll().
"""

import json
import os
import queue
import re
import signal
import subprocess
import threading
import time

from . import tiles

# After SIGINT the CLI stops between bands of rows (~65,536 texels, seconds at most);
# a child that is still alive after this is killed and its temporary file removed here.
CANCEL_GRACE_S = 20.0


class BakeProcess:
    """One bake: start(), then poll() until it returns False; cancel() at any time.

    After the end, `state` is 'done', 'failed' or 'cancelled'; `message` says why it failed,
    `warnings` holds the CLI's warnings, `ranges` its range report ("range" events, which
    come before any progress: docs/CLI.md, "Range report"), `result` its "done" event.

    An output that is a tile pattern makes it a tile set's bake (docs/FARM.md, "Tile sets"):
    `tile`, `tile_index` and `tiles` follow the progress lines, `progress` is the set's share
    and `tile_progress` the tile's own, `finished` holds each finished tile's "tile" event;
    a cancelled set keeps its finished tiles (a re-run skips them).
    """

    def __init__(self, argv, output, cwd=None):
        self.argv = [str(a) for a in argv]
        self.output = os.path.abspath(output)
        self.cwd = cwd
        self.state = "new"
        self.progress = 0.0  # fraction of rows done, 0..1 (of the whole set)
        self.tiled = tiles.is_pattern(self.output)
        self.tile = 0  # the tile in progress (a set), its place from 1, the set's tile count
        self.tile_index = 0
        self.tiles = 0
        self.tile_progress = 0.0
        self.finished = []  # "tile" events (a set): {"tile", "status": baked|skipped, ...}
        self.progress_events = 0
        self.step_name = ""  # the CLI's stage: "ground truth", "fit", "bake", ...
        self.message = ""
        self.warnings = []
        self.ranges = []
        self.result = None
        self._error_event = None
        self._lines = queue.Queue()
        self._stderr = []
        self._threads = []
        self._proc = None
        self._cancel_at = None
        self._tmp_before = set()

    def start(self):
        self._tmp_before = self._temporaries()
        try:
            self._proc = subprocess.Popen(
                self.argv, cwd=self.cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                stderr=subprocess.PIPE, text=True, encoding="utf-8", errors="replace")
        except OSError as e:
            self.state = "failed"
            self.message = "cannot run %s: %s" % (self.argv[0], e.strerror or e)
            return False
        self.state = "running"
        # Reader threads only move text into Python containers; nothing here touches bpy.
        for pipe, sink in ((self._proc.stdout, self._lines.put), (self._proc.stderr,
                                                                   self._stderr.append)):
            t = threading.Thread(target=_pump, args=(pipe, sink), daemon=True)
            t.start()
            self._threads.append(t)
        return True

    @property
    def running(self):
        return self.state == "running"

    def poll(self):
        """Consumes the lines that arrived; returns True while the bake is still running."""
        if self.state != "running":
            return False
        self._drain()
        code = self._proc.poll()
        if code is None:
            if self._cancel_at is not None and time.monotonic() - self._cancel_at > CANCEL_GRACE_S:
                self._proc.kill()
            return True
        for t in self._threads:
            t.join(timeout=5.0)
        self._drain()
        self._finish(code)
        return False

    def wait(self, interval=0.05):
        while self.poll():
            time.sleep(interval)
        return self.state

    @property
    def cancelling(self):
        """Cancel was asked for and the CLI has not stopped yet."""
        return self.state == "running" and self._cancel_at is not None

    def cancel(self):
        """Asks the CLI to stop (SIGINT: it removes its temporary file and exits 1)."""
        if self.state != "running" or self._cancel_at is not None:
            return
        self._cancel_at = time.monotonic()
        if os.name == "posix":
            self._proc.send_signal(signal.SIGINT)
        else:
            self._proc.terminate()

    def _drain(self):
        while True:
            try:
                line = self._lines.get_nowait()
            except queue.Empty:
                return
            self._event(line)

    def _event(self, line):
        try:
            ev = json.loads(line)
        except ValueError:
            return  # not an event line: the CLI's plain output is on stderr
        if not isinstance(ev, dict):
            return
        kind = ev.get("event")
        if kind == "progress" and ev.get("total"):
            self.progress_events += 1
            self.step_name = str(ev.get("stage", ""))
            own = min(1.0, float(ev.get("done", 0)) / float(ev["total"]))
            if ev.get("tiles"):
                # done/total are the tile's own; the set's share as docs/CLI.md gives it
                self.tile, self.tiles = int(ev.get("tile", 0)), int(ev["tiles"])
                self.tile_index = int(ev.get("tile_index", 1))
                self.tile_progress = own
                self.progress = (self.tile_index - 1 + own) / self.tiles
            else:
                self.progress = own
        elif kind == "tile" and "status" in ev:
            self.finished.append(ev)
            self.tiles = int(ev.get("tiles", self.tiles))
            self.tile_index = int(ev.get("index", self.tile_index))
            self.tile, self.tile_progress = int(ev.get("tile", self.tile)), 1.0
            self.progress = self.tile_index / float(self.tiles or 1)
        elif kind == "range":
            self.ranges.append(ev)
        elif kind == "warning":
            self.warnings.append(str(ev.get("message", "")))
        elif kind == "done":
            self.result = ev
        elif kind == "error":
            self._error_event = ev

    def _written(self):
        if not self.tiled:
            return os.path.isfile(self.output)
        folder = os.path.dirname(self.output)
        return all(os.path.isfile(os.path.join(folder, os.path.basename(str(ev.get("output")))))
                   for ev in self.finished)

    def _finish(self, code):
        if code == 0 and self.result is not None and self._written():
            self.state = "done"
            self.progress = 1.0
            return
        self._remove_temporaries()
        if self._cancel_at is not None:
            self.state = "cancelled"
            self.message = "cancelled; no file written"
            if self.tiled:
                n = len(self.finished)
                self.message = ("cancelled%s; no file written for it, %d finished tile%s kept "
                                "(a re-run skips %s)" % (
                                    " in tile %d" % self._cancelled_tile()
                                    if self._cancelled_tile() else "", n,
                                    "" if n == 1 else "s", "it" if n == 1 else "them"))
            return
        self.state = "failed"
        if self._error_event is not None:
            self.message = str(self._error_event.get("message", ""))
        if not self.message:  # usage errors (exit 2) and crashes say it on stderr only
            # All of it but the warnings: a usage error's cause is on its first line and
            # the hint to --help on the last.
            text = [l.strip() for l in "".join(self._stderr).strip().splitlines() if l.strip()]
            errors = [l for l in text if "warning:" not in l]
            self.message = " ".join(errors or text[-1:])
        if not self.message:
            self.message = "nbrdf exited with status %d" % code

    def _cancelled_tile(self):
        """The tile a cancel stopped: the CLI's error event names it; else the one in
        progress, unless it had finished (a cancel between two tiles)."""
        if self._error_event is not None and self._error_event.get("tile"):
            return int(self._error_event["tile"])
        done = {int(ev.get("tile", 0)) for ev in self.finished}
        return self.tile if self.tile and self.tile not in done else 0

    def _temporaries(self):
        """The CLI's temporary outputs beside the destination: .<name>.<random>.tmp (a set:
        one per tile, <name> the tile's)."""
        folder, name = os.path.split(self.output)
        try:
            entries = os.listdir(folder)
        except OSError:
            return set()
        names = tiles.name_regex(name) if self.tiled else re.compile(re.escape(name) + r"\Z")
        out = set()
        for e in entries:
            if e.startswith(".") and e.endswith(".tmp"):
                stem = e[1:-len(".tmp")].rpartition(".")[0]
                if names.match(stem):
                    out.add(e)
        return out

    def _remove_temporaries(self):
        # Only a killed CLI leaves one; those that existed before this bake are not ours.
        folder = os.path.dirname(self.output)
        for e in self._temporaries() - self._tmp_before:
            try:
                os.remove(os.path.join(folder, e))
            except OSError:
                pass


def _pump(pipe, sink):
    with pipe:
        for line in pipe:
            sink(line)
