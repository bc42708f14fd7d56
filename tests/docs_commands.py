#!/usr/bin/env python3
"""Runs every command of README.md and docs/*.md (ctest Docs.Commands).

Every fenced ```sh block is run, command by command, and every ```python block as one script, in a
scratch folder that looks like the repository root: `build/manylight` is the program under test,
`build/python` the module, `examples`, `scripts` and `tests` the source's, and `../shared` the
shared scenes. Blocks fenced otherwise (```text) are shown to the reader only.

So that the whole page set runs in a minute or two, commands are rewritten to small sizes:
  --spp N             at most 4
  --time-limit T      at most 2
  manylight view      gets --port 0 and --exit-after 3 (it serves until stopped)
  bench/gallery.py    renders only the Cornell box, for a second
  mpirun              gets --allow-run-as-root when run as root (not run without mpirun)
and `./scripts/...` lines (set-up, build, the whole test suite) are listed but not run: CI runs
them itself (.ci/run runs scripts/test; ../shared/tools/fresh-debian runs both of the README's).

Without ../shared the test skips (exit 77) and says so, unless MANYLIGHT_REQUIRE_SHARED=1 (CI),
where it fails. A failure names the page, the line and the command, with the end of its output.

Usage: tests/docs_commands.py --source DIR --bin PATH [--build-dir DIR] [--list] [--page PAGE ...]
"""
import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = 77
TIMEOUT = 300  # seconds for one command


def blocks(path):
    """(language, first line number, text) of each fenced block of a Markdown file."""
    out, lang, start, lines = [], None, 0, []
    for n, line in enumerate(path.read_text().splitlines(), 1):
        fence = re.match(r"^```(\w*)\s*$", line)
        if fence and lang is None:
            lang, start, lines = fence.group(1), n + 1, []
        elif line.startswith("```") and lang is not None:
            out.append((lang, start, "\n".join(lines)))
            lang = None
        elif lang is not None:
            lines.append(line)
    return out


def commands(text, first_line):
    """(line number, command) of a shell block: continuation lines joined, comments and blank
    lines left out."""
    out, pending, at = [], "", first_line
    for n, line in enumerate(text.splitlines(), first_line):
        if not pending:
            at = n
        part = line.strip() if pending else line.rstrip()
        if part.endswith("\\"):
            pending += part[:-1].rstrip() + " "
            continue
        cmd = (pending + part).strip()
        pending = ""
        if cmd and not cmd.startswith("#"):
            out.append((at, cmd))
    return out


def small(cmd):
    """The command at the sizes this test runs; None for one it does not run."""
    words = cmd.split()
    if words[0].startswith(("./scripts/", "scripts/")) or words[:2] == ["bash", "scripts/test"]:
        return None
    cmd = re.sub(r"--spp (\d+)", lambda m: f"--spp {min(int(m.group(1)), 4)}", cmd)
    cmd = re.sub(r"--time-limit (\d+(\.\d+)?)",
                 lambda m: f"--time-limit {min(float(m.group(1)), 2):g}", cmd)
    if re.search(r"manylight view ", cmd):
        cmd = re.sub(r"--port \d+", "", cmd) + " --port 0 --exit-after 3"
    if "bench/gallery.py" in cmd:
        cmd += " --scenes cornell-box --resolution 32x32 --seconds 0.5 --ref-seconds 1 --out gallery"
    if cmd.startswith("mpirun ") and os.geteuid() == 0:
        cmd = "mpirun --allow-run-as-root " + cmd[len("mpirun "):]
    return cmd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--bin", required=True, help="the manylight program")
    ap.add_argument("--build-dir", default="", help="where python/ (the module) was built")
    ap.add_argument("--list", action="store_true", help="print the commands, run nothing")
    ap.add_argument("--page", action="append", default=[],
                    help="only this page (README.md, docs/guide.md, ...; repeatable)")
    args = ap.parse_args()
    source = pathlib.Path(args.source).resolve()
    shared = pathlib.Path(os.environ.get("MANYLIGHT_SHARED_DIR") or source.parent / "shared")
    pages = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    if args.page:
        pages = [p for p in pages if str(p.relative_to(source)) in args.page]

    todo = []  # (page, line, kind, text)
    for page in pages:
        for lang, start, text in blocks(page):
            rel = page.relative_to(source)
            if lang == "sh":
                for line, cmd in commands(text, start):
                    todo.append((rel, line, "sh", cmd))
            elif lang == "python":
                todo.append((rel, start, "python", text))
    if args.list:
        for rel, line, kind, text in todo:
            print(f"{rel}:{line}: [{kind}] {small(text) if kind == 'sh' else text}")
        return 0

    if not (shared / "scenes").is_dir():
        message = f"Docs.Commands needs the shared scenes in {shared}, which are missing"
        if os.environ.get("MANYLIGHT_REQUIRE_SHARED") == "1":
            print(message + " (MANYLIGHT_REQUIRE_SHARED=1)")
            return 1
        print(message + ": skipped")
        return SKIP

    build_dir = pathlib.Path(args.build_dir) if args.build_dir else pathlib.Path(args.bin).parent
    python = os.environ.get("MANYLIGHT_PYTHON", "/usr/bin/python3")
    has_module = any((build_dir / "python").glob("manylight*.so"))
    failures, ran, skipped = [], 0, []
    with tempfile.TemporaryDirectory(prefix="manylight-docs-") as tmp:
        root = pathlib.Path(tmp) / "repo"
        (root / "build").mkdir(parents=True)
        os.symlink(shared, pathlib.Path(tmp) / "shared")
        os.symlink(pathlib.Path(args.bin).resolve(), root / "build" / "manylight")
        if has_module:
            os.symlink((build_dir / "python").resolve(), root / "build" / "python")
        for name in ("examples", "scripts", "tests", "bench", "docs"):
            os.symlink(source / name, root / name)
        env = dict(os.environ, MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")
        env.pop("PYTHONPATH", None)
        for rel, line, kind, text in todo:
            where = f"{rel}:{line}"
            if kind == "sh":
                cmd = small(text)
                if cmd is None:
                    skipped.append(f"{where}: {text} (CI runs it)")
                    continue
                needs_module = "build/python" in cmd
                if cmd.startswith("mpirun ") and not shutil.which("mpirun"):
                    skipped.append(f"{where}: {text} (no mpirun here)")
                    continue
                argv = ["bash", "-c", cmd]
            else:
                cmd = text
                needs_module = "import manylight" in text
                argv = [python, "-c", text]
                env["PYTHONPATH"] = str(root / "build" / "python")
            if needs_module and not has_module:
                skipped.append(f"{where}: the Python module is not built")
                continue
            try:
                r = subprocess.run(argv, cwd=root, env=env, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT)
                ok, output = r.returncode == 0, r.stdout
                status = f"exit {r.returncode}"
            except subprocess.TimeoutExpired as e:
                out = e.stdout or ""
                ok, output = False, out.decode(errors="replace") if isinstance(out, bytes) else out
                status = f"timed out after {TIMEOUT} s"
            env.pop("PYTHONPATH", None)
            ran += 1
            print(f"{'ok  ' if ok else 'FAIL'} {where}: {cmd if kind == 'sh' else '(python block)'}")
            if not ok:
                tail = "\n".join(output.splitlines()[-15:])
                failures.append(f"{where}: {status}\n  command: {cmd}\n{tail}")
    for s in skipped:
        print(f"not run {s}")
    print(f"{ran} commands run from {len(pages)} pages, {len(failures)} failed, "
          f"{len(skipped)} not run")
    for f in failures:
        print("\n" + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
