# SPDX-License-Identifier: Apache-2.0
"""The gyro a video embeds (GoPro GPMF, Sony, Insta360, DJI, ... whatever telemetry-parser reads),
written as Gyroflow's gcsv or read as a :class:`dynblur.GyroLog`.

Command line::

    python -m dynblur.extract_gyro clip.mp4 clip.gcsv

telemetry-parser (PyPI ``telemetry-parser``, MIT OR Apache-2.0) does the parsing. Its
``Parser(path).normalized_imu()`` gives each sample as ``{'timestamp_ms': float, 'gyro': (x, y, z)
or None, 'accl': ..., 'magn': ...}``, the rates in deg/s already turned by the file's IMU orientation
into Gyroflow's frame (x up, y left, z backward for a level camera looking forward); its
``telemetry()`` gives groups of fields, among them ``{'Metadata': {'frame_readout_time': ms,
'frame_readout_direction': 0..3}}`` where the file states the readout (as a gcsv file does). The gcsv
written here keeps those rates and times as they are (``orientation,XYZ``, ``tscale`` 0.001 s,
``gscale`` π/180 rad/s) and the readout lines when stated; :func:`from_video` reads it back with
``GyroLogOptions.gcsvAxes = 'gyroflow'``, which takes Gyroflow's frame to camera axes.
"""
import argparse
import math
import os
import sys
import tempfile
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

#: seconds per unit of the written gcsv's ``t``: telemetry-parser's milliseconds
GCSV_TSCALE = 1e-3
#: rad/s per unit of the written gcsv's ``gx, gy, gz``: normalized_imu's deg/s
GCSV_GSCALE = math.pi / 180.0


@dataclass
class VideoGyro:
    """A video's gyro as telemetry-parser reports it: Gyroflow's frame, deg/s, milliseconds."""
    source: str                                   #: the parser's camera and model ("GoPro HERO9 Black")
    times_ms: List[float] = field(default_factory=list)
    rates_deg_s: List[Tuple[float, float, float]] = field(default_factory=list)
    frame_readout_ms: Optional[float] = None      #: whole-frame readout time, ms, when the file states it
    frame_readout_direction: Optional[int] = None  #: 0 top to bottom, 1 bottom to top, 2 left to right, 3 right to left


def _readout_metadata(telemetry) -> Tuple[Optional[float], Optional[int]]:
    """The readout time (ms) and direction from any group's 'Metadata' of Parser.telemetry()."""
    time_ms, direction = None, None
    for chunk in telemetry or []:
        for group in (chunk or {}).values():
            metadata = group.get("Metadata") if isinstance(group, dict) else None
            if not isinstance(metadata, dict):
                continue
            if time_ms is None and "frame_readout_time" in metadata:
                time_ms = float(metadata["frame_readout_time"])
                if not (math.isfinite(time_ms) and time_ms >= 0):
                    raise ValueError(f"frame_readout_time {metadata['frame_readout_time']!r} is not a time >= 0 (ms)")
            if direction is None and "frame_readout_direction" in metadata:
                direction = int(metadata["frame_readout_direction"])
                if direction not in (0, 1, 2, 3):
                    raise ValueError(f"frame_readout_direction {direction} is not 0, 1, 2 or 3")
    return time_ms, direction


def gyro_from_parser_output(camera, model, imu, telemetry) -> VideoGyro:
    """A :class:`VideoGyro` from telemetry-parser's outputs: ``camera`` and ``model`` (strings or
    None), ``imu`` as ``Parser.normalized_imu()`` returns it and ``telemetry`` as
    ``Parser.telemetry()`` does (module docstring). Samples without a gyro reading are skipped;
    raises ValueError when none is left or a reading is not finite."""
    source = " ".join(str(part) for part in (camera, model) if part) or "unknown camera"
    gyro = VideoGyro(source=source)
    for k, sample in enumerate(imu or []):
        rates = sample.get("gyro")
        if rates is None:
            continue
        t = float(sample["timestamp_ms"])
        w = tuple(float(v) for v in rates)
        if len(w) != 3 or not all(math.isfinite(v) for v in (t,) + w):
            raise ValueError(f"{source}: IMU sample {k} has no finite time and three finite rates: "
                             f"timestamp_ms={sample.get('timestamp_ms')!r}, gyro={rates!r}")
        gyro.times_ms.append(t)
        gyro.rates_deg_s.append(w)
    if not gyro.times_ms:
        raise ValueError(f"{source}: the file holds no gyroscope samples")
    gyro.frame_readout_ms, gyro.frame_readout_direction = _readout_metadata(telemetry)
    return gyro


def read_video(path) -> VideoGyro:
    """The gyro embedded in the video (or log) at ``path``, read by telemetry-parser. Raises
    ImportError when telemetry-parser is not installed, ValueError naming the file when it reads no
    gyro from it."""
    try:
        import telemetry_parser
    except ImportError as e:
        raise ImportError("reading a video's gyro needs telemetry-parser: pip install telemetry-parser") from e
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise ValueError(f"{path}: no such file")
    try:
        parser = telemetry_parser.Parser(path)
        return gyro_from_parser_output(parser.camera, parser.model, parser.normalized_imu(), parser.telemetry())
    except (OSError, RuntimeError) as e:  # telemetry-parser's "Unsupported file format" and the like
        raise ValueError(f"{path}: telemetry-parser reads no gyro from it ({e})") from e
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from e


def gcsv_text(gyro: VideoGyro, note: str = "") -> str:
    """The gcsv text of ``gyro``: Gyroflow's frame (``orientation,XYZ``), t in ms, rates in deg/s."""
    clean = lambda text: text.replace(",", " ").replace("\n", " ").strip()  # noqa: E731
    lines = ["GYROFLOW IMU LOG", "version,1.3", "id," + clean(gyro.source).replace(" ", "_"), "orientation,XYZ"]
    if note:
        lines.append("note," + clean(note))
    if gyro.frame_readout_ms is not None:
        lines.append(f"frame_readout_time,{gyro.frame_readout_ms!r}")
    if gyro.frame_readout_direction is not None:
        lines.append(f"frame_readout_direction,{gyro.frame_readout_direction}")
    lines += [f"tscale,{GCSV_TSCALE!r}", f"gscale,{GCSV_GSCALE!r}", "t,gx,gy,gz"]
    lines += [f"{t!r},{w[0]!r},{w[1]!r},{w[2]!r}" for t, w in zip(gyro.times_ms, gyro.rates_deg_s)]
    return "\n".join(lines) + "\n"


def _load_gcsv(path, options=None):
    """GyroLog.load(path) with ``options`` (or the defaults) read in Gyroflow's frame."""
    from . import GyroLog, GyroLogOptions
    chosen = GyroLogOptions()
    if options is not None:
        for name in ("orientation", "cameraFromGyro", "timeOrigin", "dropRepeatedSamples", "estimateBias",
                     "stillThreshold", "stillMinDuration"):
            setattr(chosen, name, getattr(options, name))
    chosen.gcsvAxes = "gyroflow"
    return GyroLog.load(os.fspath(path), chosen)


def write_gcsv(gyro: VideoGyro, out_path, note: str = "", options=None):
    """Writes ``gyro`` as gcsv to ``out_path`` whole or not at all: the text goes to a file beside it,
    is read back by GyroLog.load (which refuses, naming line and field, what it would refuse later),
    and only then takes the name. Returns the GyroLog read back."""
    out_path = os.fspath(out_path)
    directory = os.path.dirname(os.path.abspath(out_path))
    fd, scratch = tempfile.mkstemp(prefix=".extract_gyro_", suffix=".gcsv", dir=directory)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(gcsv_text(gyro, note))
        log = _load_gcsv(scratch, options)
        os.replace(scratch, out_path)
        return log
    finally:
        if os.path.exists(scratch):
            os.remove(scratch)


def from_video(filename, options=None):
    """GyroLog.fromVideo: the gyro a video embeds, as a GyroLog in camera axes. ``options`` (a
    GyroLogOptions) gives the axis string, mounting rotation, repeated samples and bias estimation;
    its gcsvAxes is 'gyroflow' whatever it says (telemetry-parser's rates are in Gyroflow's frame),
    its column and unit options do not apply. frameReadoutTime and frameReadoutDirection are the
    file's where telemetry-parser reports them."""
    gyro = read_video(filename)
    with tempfile.TemporaryDirectory(prefix="dynblur_video_gyro_") as directory:
        return write_gcsv(gyro, os.path.join(directory, "gyro.gcsv"), options=options)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m dynblur.extract_gyro",
        description="Writes the gyro a video embeds (GoPro GPMF, Sony, Insta360, DJI, ... as telemetry-parser "
                    "reads them) as Gyroflow's gcsv: rates in Gyroflow's frame (orientation XYZ), t in ms, rates in "
                    "deg/s, frame_readout_time and frame_readout_direction where the file states them. Read it with "
                    "GyroLog.load and GyroLogOptions.gcsvAxes = 'gyroflow' (programs: --gyro-gcsv-axes gyroflow).",
        epilog="Exit status: 0 written, 1 no gyro read or the log refused (nothing written), 2 bad usage.")
    parser.add_argument("video", help="the video (or telemetry log) to read")
    parser.add_argument("output", help="the gcsv file to write")
    parser.add_argument("--force", action="store_true", help="replace an existing output file")
    args = parser.parse_args(argv)
    from . import error as refused  # the reader's refusal names the line and the field
    if os.path.exists(args.output) and not args.force:
        parser.error(f"{args.output} exists; --force replaces it")
    try:
        gyro = read_video(args.video)
        log = write_gcsv(gyro, args.output, note=f"extracted from {os.path.basename(args.video)} by "
                                                 "dynblur.extract_gyro with telemetry-parser")
    except (ImportError, ValueError) as e:
        print(f"extract_gyro: {e}", file=sys.stderr)
        return 1
    except refused as e:
        print(f"extract_gyro: {args.video}: the extracted log is refused: {e}", file=sys.stderr)
        return 1
    span = log.times[-1] - log.times[0]
    readout = "not stated" if math.isnan(log.frameReadoutTime) else f"{log.frameReadoutTime * 1e3:.3f} ms"
    print(f"{args.output}: {len(log.times)} gyro samples from {gyro.source}, {span:.3f} s "
          f"({(len(log.times) - 1) / span:.1f} Hz), frame readout {readout}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
