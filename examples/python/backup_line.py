#!/usr/bin/env python3
"""Backs up every drive of one line (several MACIDs on one port, RS485) into
one file per drive, through the lmcfg Python package.

    backup_line.py --port /dev/ttyUSB0 --id 0x11 --id 0x12 --out-dir backups/

Each drive's file is OUT_DIR/drive-<MACID>.json (or .xml with --format xml).
A drive that fails is reported and the others are still read; the exit code
is then the failure's (lmcfg.Error.exit_code: 4 link, 5 drive refused), as
`lmcfg fleet backup` does.

Try it without hardware: `lmcfg sim --pty --state a.json --state b.json`
serves two simulated drives (distinct MACIDs) on one pseudo-terminal.
"""

import argparse
import sys
from pathlib import Path

import lmcfg


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--port", required=True, help="serial device, tcp://host:port or sim:FILE")
    ap.add_argument("--id", action="append", required=True, type=lambda s: int(s, 0),
                    help="MACID of a drive on the line (repeat for each)")
    ap.add_argument("--baud", type=int, default=57600)
    ap.add_argument("--checksum", default="none")
    ap.add_argument("--out-dir", type=Path, default=Path("."))
    ap.add_argument("--format", choices=["json", "xml"], default="json")
    args = ap.parse_args()

    args.out_dir.mkdir(parents=True, exist_ok=True)
    worst = 0
    for macid in args.id:
        link = lmcfg.Link(args.port, baud=args.baud, id=macid, checksum=args.checksum)
        out = args.out_dir / f"drive-{macid:02X}.{args.format}"
        try:
            with link.open() as drive:
                cfg = drive.backup(labels={"line_port": args.port})
            cfg.save(out)
        except lmcfg.Error as e:
            print(f"drive {macid:02X}h: {e} (exit {e.exit_code})", file=sys.stderr)
            worst = max(worst, e.exit_code)
            continue
        print(f"drive {macid:02X}h: {len(cfg.parameters)} parameter(s), {len(cfg.curves)} "
              f"curve(s), {len(cfg.ct_entries)} command table entries -> {out}")
    return worst


if __name__ == "__main__":
    sys.exit(main())
