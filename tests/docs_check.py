#!/usr/bin/env python3
"""The docs' links resolve and the commands they name exist.

Usage: tests/docs_check.py SOURCE_DIR GIHARNESS_BINARY

Reads README.md, docs/**/*.md and every other *.md of the source tree
(build folders, hidden folders and out/ left out) and checks:

1. every relative link, [text](path) or [text](path#anchor) or ![alt](path),
   names a file or folder that exists, and an #anchor into a Markdown file
   names one of its headings (GitHub's anchors: the heading's text, lowercase,
   punctuation but '-' and '_' removed, spaces turned to '-', '-1', '-2', ...
   for repeats);
2. every giharness command named in a code span or a fenced code block
   (`giharness run ...`, `build/giharness nightly ...`, `giharness baseline
   update ...`) exists: `GIHARNESS_BINARY <cmd> [<sub>] --help` exits 0 and
   its usage line names the command (the binary prints its top-level help,
   exit 0, for a command it does not know).

Exit 0 with a one-line summary; exit 1 listing each broken link and unknown
command as file:line. Standard library only.
"""
import os
import re
import subprocess
import sys
import unicodedata

SKIP_DIRS = {"out", "node_modules", "__pycache__"}

FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"(`+)(.+?)\1")
# [text](target) and ![alt](target); the target ends at whitespace or ')'.
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
COMMAND = re.compile(r"(?<![\w.-])(?:[\w.~-]*/)*giharness[ \t]+([a-z][a-z0-9-]*)(?:[ \t]+([a-z][a-z0-9-]*))?")
# What may stand before a command that starts there: environment settings and
# wrappers (`X=1 time -v build/giharness run`), after a shell separator or at
# the start of the code. Elsewhere `giharness` is an argument or a folder
# (`dpkg -r giharness`, `share/giharness beside it`).
WRAPPERS = re.compile(r"(?:\s+|(?<![\w/.=-])(?:[A-Za-z_]\w*=\S*|(?:/usr/bin/)?time|-v|exec|nice|timeout\s+\S+))$")
SEPARATORS = ("&&", "||", ";", "|", "(", "$(", "do", "then", "$")


def starts_command(before):
    while True:
        m = WRAPPERS.search(before)
        if not m or m.start() == len(before):
            break
        before = before[:m.start()]
    return before == "" or before.endswith(SEPARATORS)


def markdown_files(root):
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        rel = os.path.relpath(dirpath, root)
        dirnames[:] = sorted(
            d for d in dirnames
            if not d.startswith(".") and not d.startswith("build") and d not in SKIP_DIRS
            and not (rel == "." and d == "shared"))
        for f in sorted(filenames):
            if f.endswith(".md"):
                found.append(os.path.join(dirpath, f))
    return found


def heading_text(raw):
    """A heading's text as GitHub renders it (inline Markdown removed)."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", raw)  # links, images
    text = text.replace("`", "")
    text = re.sub(r"<[^>]+>", "", text)                        # inline HTML
    text = re.sub(r"(\*\*|__)(.+?)\1", r"\2", text)
    text = re.sub(r"(?<!\w)[*_](.+?)[*_](?!\w)", r"\1", text)
    return text


def slug(text):
    out = []
    for ch in heading_text(text).strip().lower():
        cat = unicodedata.category(ch)
        if ch in " -_" or cat[0] in "LN" or cat == "Mn":
            out.append(ch)
    return "".join(out).replace(" ", "-")


def scan(path):
    """(lines outside code with their numbers, code pieces with their numbers, anchors)."""
    prose, code, anchors, seen = [], [], set(), {}
    in_fence = None
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for n, line in enumerate(lines, 1):
        m = FENCE.match(line)
        if m:
            if in_fence is None:
                in_fence = m.group(1)
            elif m.group(1) == in_fence:
                in_fence = None
            continue
        if in_fence is not None:
            code.append((n, line))
            continue
        for c in INLINE_CODE.finditer(line):
            code.append((n, c.group(2)))
        prose.append((n, INLINE_CODE.sub(lambda c: " " * len(c.group(0)), line)))
        h = HEADING.match(line)
        if h:
            s = slug(h.group(2))
            k = seen.get(s, 0)
            anchors.add(s if k == 0 else f"{s}-{k}")
            seen[s] = k + 1
        for a in re.finditer(r"<a\s+(?:name|id)=\"([^\"]+)\"", line):
            anchors.add(a.group(1))
    return prose, code, anchors


class Commands:
    def __init__(self, binary):
        self.binary = binary
        self.cache = {}

    def help(self, words):
        key = tuple(words)
        if key not in self.cache:
            try:
                r = subprocess.run([self.binary, *words, "--help"], capture_output=True, text=True, timeout=60)
                self.cache[key] = (r.returncode, r.stdout + r.stderr)
            except (OSError, subprocess.TimeoutExpired) as e:
                self.cache[key] = (None, str(e))
        return self.cache[key]

    def exists(self, cmd, sub):
        """None when the command exists, else why not."""
        rc, out = self.help([cmd])
        if rc != 0:
            return f"`{cmd} --help` exited {rc}"
        if not re.search(r"Usage: \S+ " + re.escape(cmd) + r"(\s|$)", out):
            return f"not a command of {os.path.basename(self.binary)}"
        if sub and "Subcommands:" in out:
            rc, out = self.help([cmd, sub])
            if rc != 0 or not re.search(r"Usage: \S+ " + re.escape(cmd) + " " + re.escape(sub) + r"(\s|$)", out):
                return f"`{cmd}` has no subcommand `{sub}`"
        return None


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    root, binary = os.path.abspath(argv[1]), os.path.abspath(argv[2])
    if not os.access(binary, os.X_OK):
        print(f"docs_check: {binary} is not an executable", file=sys.stderr)
        return 2
    files = markdown_files(root)
    scanned = {os.path.abspath(p): scan(p) for p in files}
    anchors_of = {p: s[2] for p, s in scanned.items()}

    def anchors(path):
        if path not in anchors_of:
            anchors_of[path] = scan(path)[2]
        return anchors_of[path]

    problems, links, commands = [], 0, 0
    cli = Commands(binary)
    for path in files:
        path = os.path.abspath(path)
        rel = os.path.relpath(path, root)
        prose, code, _ = scanned[path]
        for n, line in prose:
            targets = [m.group(1) for m in LINK.finditer(line)]
            m = REF_DEF.match(line)
            if m:
                targets.append(m.group(1))
            for t in targets:
                if re.match(r"^[a-z][a-z0-9+.-]*:", t, re.I):  # http:, mailto:, ...
                    continue
                links += 1
                file_part, _, anchor = t.partition("#")
                target = path if not file_part else os.path.normpath(os.path.join(os.path.dirname(path), file_part))
                if file_part and not os.path.exists(target):
                    problems.append(f"{rel}:{n}: broken link {t}: no {os.path.relpath(target, root)}")
                    continue
                if anchor and target.endswith(".md") and os.path.isfile(target) and anchor not in anchors(target):
                    problems.append(f"{rel}:{n}: broken link {t}: no heading #{anchor} in {os.path.relpath(target, root)}")
        for n, text in code:
            for m in COMMAND.finditer(text):
                if not starts_command(text[:m.start()]):
                    continue
                commands += 1
                why = cli.exists(m.group(1), m.group(2))
                if why:
                    problems.append(f"{rel}:{n}: unknown command `giharness {m.group(1)}`: {why}")
    if problems:
        for p in problems:
            print(p)
        print(f"docs_check: {len(problems)} problem(s) in {len(files)} Markdown files")
        return 1
    print(f"docs_check: {len(files)} Markdown files, {links} relative links resolve, "
          f"{commands} giharness command names exist ({len(cli.cache)} distinct)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
