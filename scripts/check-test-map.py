#!/usr/bin/env python3
"""Every library source with logic has a test file named after it: for each
lib/<layer>/<name>.cpp the file tests/<layer>/test_<name>.cpp exists, unless
ALLOWED below says why not (no logic of its own, or tested under another name:
then the files named there must exist). An allowlist entry whose source is
gone, or that now has its test file, is stale and fails too.
usage: check-test-map.py SOURCE_DIR"""
import os, sys

# Tested under another name: source -> (where, why).
ALLOWED = {
    # The JSON and XML readers and writers walk the tables of fields.cpp;
    # test_fields.cpp round-trips every field of every table through both
    # formats, test_json_io.cpp/test_xml_io.cpp read and write every layer and
    # member and check each kind of field's messages.
    "config/json_fields.cpp": ("tests/config/test_fields.cpp tests/config/test_json_io.cpp",
                               "walks the field tables for JSON"),
    "config/xml_fields.cpp": ("tests/config/test_fields.cpp tests/config/test_xml_io.cpp",
                              "walks the field tables for XML"),
    "config/json_write.cpp": ("tests/config/test_json_io.cpp tests/config/test_config_io.cpp",
                              "the JSON document's frame, written"),
    "config/xml_write.cpp": ("tests/config/test_xml_io.cpp tests/config/test_config_io.cpp",
                             "the XML document's frame, written"),
    # Version 1 files: read by these and migrated (migrate.cpp) in one step.
    "config/json_read_v1.cpp": ("tests/config/test_migrate.cpp",
                                "version 1 JSON, read for the migration"),
    "config/xml_read_v1.cpp": ("tests/config/test_migrate.cpp",
                               "version 1 XML, read for the migration"),
    # The compiler's rows and its SQLite writer are its two halves; the
    # compiler's tests give it sources and check rows, messages and the file.
    "db/compiler_rows.cpp": ("tests/db/test_compiler.cpp", "the compiler's row checks"),
    "db/compiler_write.cpp": ("tests/db/test_compiler.cpp", "the compiler's SQLite writer"),
    # The simulated DeviceNet controller is the peer the master is tested against.
    "sim/devicenet_controller.cpp": ("tests/devicenet/test_master.cpp",
                                     "the peer of the DeviceNet master's tests"),
    # The simulated drive's block transfers and fault model are parts of the
    # drive and its link; their tests drive them through those.
    "sim/drive_blocks.cpp": ("tests/sim/test_drive.cpp tests/sim/test_sim_manual.cpp",
                             "curve and command table transfers of the simulated drive"),
    "sim/faults.cpp": ("tests/sim/test_link.cpp tests/client/test_reliability_faults.cpp",
                       "the fault model, through the simulated link"),
    # The restore plan's phases: checks against the target and the tables.
    "ops/restore_check.cpp": ("tests/ops/test_restore_plan.cpp",
                              "the plan's checks against the target"),
    "ops/restore_tables.cpp": ("tests/ops/test_restore_plan.cpp tests/ops/test_restore_second_drive.cpp",
                               "the plan's curve and command table steps"),
    # The service in four files over one private header: its tests go through
    # the public Service.
    "serve/service_jobs.cpp": ("tests/serve/test_service.cpp", "the service's backup and status runs"),
    "serve/service_metrics.cpp": ("tests/serve/test_service.cpp", "metrics and the daily summary"),
    "serve/service_restore.cpp": ("tests/serve/test_service.cpp tests/serve/test_serve_plan.cpp",
                                  "the service's restores"),
    # lmcfg ui's desk in three files over one private header, its pages in
    # two: the jobs' work and the drive's pages are driven through the server.
    "ui/desk_ops.cpp": ("tests/ui/test_ui_server.cpp tests/ui/test_desk.cpp",
                        "the desk's find, backup, compare and plan jobs"),
    # lmcfg serve's and lmcfg ui's shared checks, unit-tested beside the ui's
    # tests (the console's own run over HTTP in tests/serve/test_console.cpp).
    "serve/request_checks.cpp": ("tests/ui/test_request_checks.cpp tests/serve/test_console.cpp",
                                 "the Host and Origin checks both servers share"),
    "ui/desk_write.cpp": ("tests/ui/test_ui_server.cpp", "the desk's restore and undo writes"),
    "ui/server.cpp": ("tests/ui/test_ui_server.cpp", "the page's HTTP API end to end (test_server is sim's)"),
    "ui/pages_drive.cpp": ("tests/ui/test_pages.cpp tests/ui/test_ui_server.cpp",
                           "the drive, job and plan pages"),
    # Platform files split out of the file whose tests cover them.
    "transport/serial_settings.cpp": ("tests/transport/test_serial.cpp",
                                      "the line settings, tested with the serial port"),
    "can/socketcan.cpp": ("tests/can/test_link.cpp", "SocketCAN, beside slcan's link"),
    "ops/platform.cpp": ("tests/ops/test_recovery.cpp tests/ops/test_audit.cpp",
                         "the state folder and the user, through their callers"),
    # Scanning needs a bus of drives at unknown settings: the CLI tests run it.
    "link/scan.cpp": ("tests/tools/test_cli_scan_first_steps.cpp tests/tools/test_rfc2217_cli.cpp",
                      "scan over a pseudo-terminal and through ser2net"),
}

def main(source):
    lib = os.path.join(source, "lib")
    sources = set()
    for layer in sorted(os.listdir(lib)):
        d = os.path.join(lib, layer)
        if not os.path.isdir(d):
            continue
        for f in sorted(os.listdir(d)):
            if f.endswith(".cpp"):
                sources.add(f"{layer}/{f}")
    failures = []
    for src in sorted(sources):
        layer, name = src.split("/")
        # NAME_win32.cpp is tested by NAME's tests, run under Wine (docs/windows.md).
        base = name[:-len("_win32.cpp")] + ".cpp" if name.endswith("_win32.cpp") else name
        if base != name and f"{layer}/{base}" in ALLOWED:
            continue
        test = f"tests/{layer}/test_{base}"
        has_test = os.path.exists(os.path.join(source, test))
        if src in ALLOWED:
            where, why = ALLOWED[src]
            if has_test:
                failures.append(f"lib/{src}: {test} exists; remove its entry from ALLOWED "
                                "in scripts/check-test-map.py")
            for w in where.split():
                if not os.path.exists(os.path.join(source, w)):
                    failures.append(f"lib/{src}: ALLOWED says it is tested in {w}, "
                                    "which does not exist")
        elif not has_test:
            failures.append(f"lib/{src}: no {test}; write it (or list the source in ALLOWED "
                            "of scripts/check-test-map.py with the file that tests it)")
    for src in sorted(set(ALLOWED) - sources):
        failures.append(f"scripts/check-test-map.py: lib/{src} does not exist; remove its entry")
    for f in failures:
        print(f, file=sys.stderr)
    covered = sum(1 for s in sources
                  if os.path.exists(os.path.join(source, "tests", s.replace("/", "/test_", 1))))
    print(f"{covered} of {len(sources)} lib sources have tests/<layer>/test_<name>.cpp, "
          f"{len(ALLOWED)} are tested under another name")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
