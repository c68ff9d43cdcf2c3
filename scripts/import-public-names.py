#!/usr/bin/env python3
"""Imports public parameter names (docs/references.md "public parameter names") into
upid-db/parameters.tsv, each row into the profile its source names (docs/upid-db.md
"Names from public sources" has the rules and the counts).

Usage: scripts/import-public-names.py NAMES_TSV UPID_DB_DIR   (rewrites parameters.tsv)

NAMES_TSV: a header line, then one row per name: upid_hex, name, type,
unit_or_scale, series_or_firmware (the family or firmware it was seen for),
source_repo, source_path (the public repository and file it came from).

A row whose series names no family this project has a profile for is skipped and
listed. A row for a UPID the E1100 profile already has fills only empty fields of
that row (the seed's fields win), and only where a name from another family cannot
label a value of this one (B1100 UPIDs differ, LinRS 3V27 p26): the source names
E1100, or the seed gives the same meaning for the same UPID.
"""
import csv
import sys

# Series text -> profiles. First match wins; order matters.
RULES = [
    ("B1100 (SG4)", ["b1100-mc"]),
    ("B1100/E1100 per doc title", ["e1100-mc-linrs"]),  # B1100 UPIDs differ (3V27 p26)
    ("LinRS manual 0185-1082 3V27", ["e1100-mc-linrs", "c1100-mc-linrs", "e1200-mc-linrs"]),
    ("MC SW manual 4.3.4", ["a1100-mc-canopen", "c1100-mc-linrs", "e1200-mc-linrs"]),
    ("CANopen SG5-SG7", ["a1100-mc-canopen", "c1100-mc-linrs", "e1200-mc-linrs"]),
    ("A1100 (SG7)", ["a1100-mc-canopen"]),
    ("E1250-EC-UC, LinRS", ["e1200-mc-linrs"]),
    ("C1100, LinRS", ["c1100-mc-linrs"]),
    ("LinUDP DLL 2.1.1 (C1250/E1250/E1450/C1450)", ["c1250-mc-linudp", "e1200-mc-linrs"]),
    ("LinUDP DLL 2.1.1", ["c1250-mc-linudp"]),
    ("C1250", ["c1250-mc-linudp"]),
    ("Aug 2023); E1100", ["e1100-mc-linrs"]),
]

# The seed gives the same meaning for these unnamed E1100 UPIDs (seed 001 §6 example:
# "changes the maximal current of the position controller set A (UPID 13A6)"), so a
# name/type/unit seen for another family (remcohn/linUDP, C1250, whose constants are
# named E1100_*) may fill the E1100 row's empty fields. Rows the seed already names
# (13A2h, 170Ch) keep the seed's fields.
SEED_AGREES_E1100 = {"13A6"}

UNITS = [  # (unit_or_scale prefix, unit, scale)
    ("0.1 um", "mm", "0.0001"), ("0.0001 mm", "mm", "0.0001"),
    ("1e-6 m/s", "m/s", "0.000001"), ("0.000001 m/s", "m/s", "0.000001"),
    ("1e-5 m/s2", "m/s2", "0.00001"), ("0.00001 m/s2", "m/s2", "0.00001"),
    ("0.001 A (1 mA)", "A", "0.001"), ("raw/1000 = A", "A", "0.001"),
    ("0.1 A/mm", "A/mm", "0.1"), ("0.1 A/(m/s)", "A/(m/s)", "0.1"),
    ("1 ms", "ms", "1"), ("0.1 ms", "ms", "0.1"), ("0.01 V", "V", "0.01"),
    ("0.1 W", "W", "0.1"), ("0.1 C", "degC", "0.1"), ("1 um/s", "m/s", "0.000001"),
    ("0.1 N", "N", "0.1"),
]
TYPES = {"UINT16", "SINT16", "UINT32", "SINT32", "UINT8", "SINT8", "BOOL"}
HEADER = ("upid profiles layer name path type address_usage min max default unit scale "
          "enum comm description source").split()


def layer_of(u):
    v = int(u, 16)
    for lo, name in ((0, "OS"), (0x1000, "MC"), (0x2000, "Intf"), (0x3000, "Appl")):
        if lo <= v <= lo + 0xEFF:
            return name
    return "Other"


def convert(p):
    unit, scale, notes = "", "", []
    us = p["unit_or_scale"].strip()
    for prefix, u, s in UNITS:
        if us.startswith(prefix) and not us.startswith("0.980"):
            unit, scale = u, s
            break
    if us and not unit:
        notes.append(("values: " if p["type"] == "enum" else "unit as given: ") + us)
    typ = p["type"].split(" ")[0] if p["type"].split(" ")[0] in TYPES else ""
    if p["type"] and not typ:
        notes.append("type as given: " + p["type"])
    prov = "public: %s %s (seen for: %s)" % (p["source_repo"], p["source_path"],
                                             p["series_or_firmware"])
    name = p["name"]
    if name.startswith("(unnamed") or "name not given" in name:  # a use, not a name
        notes.insert(0, "no name given; as described: " + name)
        name = ""
    return {"name": name, "type": typ, "unit": unit, "scale": scale,
            "notes": notes, "source": prov}


def main(peer, db):
    rows = list(csv.DictReader(open(peer, encoding="utf-8"), delimiter="\t"))
    path = db + "/parameters.tsv"
    lines = open(path, encoding="utf-8").read().splitlines()
    head = lines[0].split("\t")
    assert head == HEADER, head
    have = [dict(zip(HEADER, l.split("\t"))) for l in lines[1:] if l and not l.startswith("#")]
    e1100 = {r["upid"]: r for r in have if r["profiles"] == "e1100-mc-linrs"}
    new, skipped = {}, []
    for p in rows:
        profs = next((ps for key, ps in RULES if key in p["series_or_firmware"]), None)
        if profs is None:
            skipped.append(p)
            continue
        c = convert(p)
        profs = list(profs)
        if "e1100-mc-linrs" in profs and p["upid_hex"] in e1100:
            r = e1100[p["upid_hex"]]
            for k in ("name", "type", "unit", "scale"):
                if not r[k] and c[k]:
                    r[k] = c[k]
            r["source"] += "; " + c["source"]
            profs.remove("e1100-mc-linrs")
        if not profs:
            continue
        key = (p["upid_hex"], ",".join(profs))
        if key in new:  # the same UPID from a second source: fill, join provenance
            r = new[key]
            for k in ("type", "unit", "scale"):
                if not r[k] and c[k]:
                    r[k] = c[k]
            r["description"] += "" if not c["notes"] else " " + "; ".join(c["notes"]) + "."
            r["source"] += "; " + c["source"]
            continue
        desc = "; ".join(c["notes"]) + ("." if c["notes"] else "")
        new[key] = dict(zip(HEADER, [p["upid_hex"], ",".join(profs), layer_of(p["upid_hex"]),
                                      c["name"], "", c["type"], "", "", "", "", c["unit"],
                                      c["scale"], "", "1" if p["upid_hex"] == "2080" else "",
                                      desc.strip(), c["source"]]))
    # Seed-agreement for E1100 rows: a C1250 name fills the empty E1100 fields only
    # for the UPIDs whose meaning seed 001/003 states.
    for (u, profs), r in new.items():
        if u in SEED_AGREES_E1100 and u in e1100:
            t = e1100[u]
            for k in ("name", "type", "unit", "scale"):
                if not t[k] and r[k]:
                    t[k] = r[k]
            if "public:" not in t["source"]:
                t["source"] += "; " + r["source"] + " (meaning agrees with the seed)"
    out = [lines[0]] + ["\t".join(r[h] for h in HEADER) for r in have]
    out += ["\t".join(r[h] for h in HEADER) for r in new.values()]
    open(path, "w", encoding="utf-8").write("\n".join(out) + "\n")
    print("imported %d rows into %d new rows; skipped %d:" % (len(rows) - len(skipped),
                                                             len(new), len(skipped)))
    for p in skipped:
        print("  %s %s (%s)" % (p["upid_hex"], p["name"], p["series_or_firmware"]))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
