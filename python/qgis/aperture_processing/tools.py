"""Finding and running the aperture tools for the algorithms.

A tool runs as a child process with --progress=json (docs/cli.md,
"Progress for scripts"): each line on its stdout is a stage's progress,
which goes to the Processing feedback; its stderr goes to the log. Cancel
sends SIGINT, on which a tool stops within a second and removes its
unfinished outputs.
"""

import json
import os
import queue
import shlex
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

from qgis.core import QgsProcessingException

# The Processing setting that names the tools' folder (empty: found as below).
BIN_DIR_SETTING = "APERTURE_BIN_DIR"
# The same as an environment variable, for scripts and tests.
BIN_DIR_VARIABLE = "APERTURE_BIN_DIR"

# How long a tool may take to stop after SIGINT before it is killed: the
# tools stop within a second; a second signal would kill them too.
STOP_GRACE_SECONDS = 10.0

# The stages of --progress json, in words for the Processing dialog.
STAGE_TEXT = {
    "baking": "Baking the aperture map",
    "shading": "Shading the relief",
    "tracing": "Ray tracing the reference",
    "rendering": "Rendering frames",
}


def _configured_bin_dir():
    """The folder set in Processing's options, or None (no Processing)."""
    try:
        from processing.core.ProcessingConfig import ProcessingConfig
    except ImportError:
        return None
    value = ProcessingConfig.getSetting(BIN_DIR_SETTING)
    return value or None


def _installed_bin_dir():
    """PREFIX/bin when the plugin is installed as PREFIX/share/aperture/qgis/aperture_processing."""
    plugin_dir = Path(__file__).resolve().parent
    return plugin_dir.parents[3] / "bin" if len(plugin_dir.parents) > 3 else None


def tool_path(name):
    """The executable of tool `name` (aal-bake): in the configured folder,
    $APERTURE_BIN_DIR, the plugin's install prefix, else on PATH."""
    searched = []
    for folder in (_configured_bin_dir(), os.environ.get(BIN_DIR_VARIABLE), _installed_bin_dir()):
        if not folder:
            continue
        candidate = Path(folder) / name
        searched.append(str(folder))
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    found = shutil.which(name)
    if found:
        return found
    raise QgsProcessingException(
        f"{name} not found (looked in {', '.join(searched) or 'no configured folder'} and on "
        f"PATH): "
        f"install aperture, or set the folder of its tools in Processing > Options > Providers > "
        f"Aperture (or ${BIN_DIR_VARIABLE})")


def _pump(stream, kind, lines):
    for line in stream:
        lines.put((kind, line.rstrip("\n")))
    lines.put((kind, None))


def _report_progress(line, feedback, state):
    """One --progress json line into the feedback; False when it is not one."""
    try:
        report = json.loads(line)
        stage, done, total = report["stage"], int(report["done"]), int(report["total"])
    except (ValueError, KeyError, TypeError):
        return False
    if stage != state.get("stage"):
        state["stage"] = stage
        feedback.setProgressText(STAGE_TEXT.get(stage, stage))
    if total > 0:
        feedback.setProgress(100.0 * done / total)
    return True


def run_tool(name, arguments, feedback):
    """Runs tool `name` with `arguments` (a list of strings) and its progress
    as JSON lines into `feedback`. Raises QgsProcessingException when it
    fails (with its last messages) or when `feedback` is canceled (the tool
    stopped by SIGINT, its unfinished outputs removed by it)."""
    command = [tool_path(name), *arguments, "--progress=json"]
    feedback.pushCommandInfo(" ".join(shlex.quote(part) for part in command))
    try:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, bufsize=1)
    except OSError as error:
        raise QgsProcessingException(f"cannot run {command[0]}: {error}") from error
    lines = queue.Queue()
    readers = [threading.Thread(target=_pump, args=(process.stdout, "out", lines), daemon=True),
               threading.Thread(target=_pump, args=(process.stderr, "err", lines), daemon=True)]
    for reader in readers:
        reader.start()
    messages = []
    state = {}
    open_streams = 2
    canceled_at = None
    while open_streams > 0:
        if canceled_at is None and feedback.isCanceled():
            canceled_at = time.monotonic()
            process.send_signal(signal.SIGINT)
        if canceled_at is not None and time.monotonic() - canceled_at > STOP_GRACE_SECONDS:
            process.kill()
        try:
            kind, line = lines.get(timeout=0.1)
        except queue.Empty:
            continue
        if line is None:
            open_streams -= 1
        elif kind == "out":
            if not _report_progress(line, feedback, state):
                feedback.pushConsoleInfo(line)
        else:
            messages.append(line)
            feedback.pushConsoleInfo(line)
    code = process.wait()
    for reader in readers:
        reader.join()
    process.stdout.close()
    process.stderr.close()
    if canceled_at is not None:
        raise QgsProcessingException(f"{name}: canceled")
    if code != 0:
        last = "\n".join(messages[-5:]) or "(no message)"
        raise QgsProcessingException(f"{name} failed (exit {code}):\n{last}")
    return messages
