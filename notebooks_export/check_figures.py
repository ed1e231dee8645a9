#!/usr/bin/env python3
"""Checks the figures of a results folder against notebooks_export/figures.txt.

    check_figures.py RESULTS_DIR

Every listed file must exist under RESULTS_DIR/figures/, be non-empty and start with its
format's signature (PDF: %PDF-, PNG: the 8-byte PNG signature); a PDF or PNG there that the
list does not name is an error too (the list is the notebook's complete output).
Exit status 0 when all hold, 1 otherwise (each problem on its own line on stderr).
"""
import pathlib
import sys

SIGNATURES = {".pdf": b"%PDF-", ".png": b"\x89PNG\r\n\x1a\n"}


def expected():
    listing = pathlib.Path(__file__).with_name("figures.txt")
    return [line.strip() for line in listing.read_text().splitlines() if line.strip() and not line.startswith("#")]


def main(argv):
    if len(argv) != 2:
        print("usage: check_figures.py RESULTS_DIR", file=sys.stderr)
        return 2
    figures = pathlib.Path(argv[1]) / "figures"
    names = expected()
    problems = []
    for name in names:
        path = figures / name
        if not path.is_file():
            problems.append(f"missing: {path}")
            continue
        head = path.read_bytes()[:16]
        if not head:
            problems.append(f"empty: {path}")
        sig = SIGNATURES.get(path.suffix)
        if sig and not head.startswith(sig):
            problems.append(f"not a {path.suffix[1:].upper()} file (bad signature): {path}")
    if figures.is_dir():
        for path in sorted(figures.iterdir()):
            if path.suffix in SIGNATURES and path.name not in names:
                problems.append(f"written but not listed in figures.txt: {path}")
    for p in problems:
        print(p, file=sys.stderr)
    if not problems:
        print(f"{len(names)} figure files present and well-formed in {figures}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
