#!/usr/bin/env python3
"""tests/docs/check_links.py — every relative link in the README and docs/ resolves.

    python3 tests/docs/check_links.py REPO_ROOT

Checks README.md and docs/**/*.md: each markdown link `[text](target)`, image
`![alt](target)` and reference definition `[label]: target` whose target is not
a URL (scheme:...) must name a file or folder inside the repository, and a
`#anchor` (alone: this file; after a .md path: that file) must be a heading
of the target, by GitHub's rule for heading ids. Code blocks and code spans
are skipped. Prints each broken link as FILE:LINE: problem; exit 1 if any.
Python 3 standard library only.
"""
import os
import re
import sys
import unicodedata

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*(<[^>]*>|[^)\s]+)(?:\s+\"[^\"]*\"|\s+'[^']*')?\s*\)")
REFDEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s{0,3}(```|~~~)")
HTML_ID = re.compile(r"<a\s+(?:name|id)=\"([^\"]+)\"", re.I)
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def strip_code_spans(line):
    return re.sub(r"(`+)(.+?)\1", "", line)


def lines_outside_code(text):
    """(line number, line) for each line outside fenced code blocks."""
    fenced = None
    for n, line in enumerate(text.splitlines(), 1):
        m = FENCE.match(line)
        if m:
            if fenced is None:
                fenced = m.group(1)
                continue
            if line.strip().startswith(fenced):
                fenced = None
                continue
        if fenced is None:
            yield n, line


def heading_text(raw):
    """A heading's text as GitHub renders it: code spans keep their content,
    links keep their text, images and HTML tags go, emphasis markers go."""
    s = re.sub(r"(`+)(.+?)\1", lambda m: m.group(2), raw)
    s = re.sub(r"!\[[^\]]*\]\([^)]*\)", "", s)
    s = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", s)
    s = re.sub(r"<[^>]+>", "", s)
    s = re.sub(r"(\*+|(?<!\w)_+|_+(?!\w))", "", s)
    return s


def slug(text):
    """GitHub's heading id: lower case; drop every character that is not a
    letter, digit, mark, space, hyphen or underscore; spaces become hyphens."""
    out = []
    for ch in text.strip().lower():
        cat = unicodedata.category(ch)
        if ch in "-_" or cat[0] in "LNM":
            out.append(ch)
        elif ch == " ":
            out.append("-")
    return "".join(out)


def anchors(path, cache={}):
    if path not in cache:
        ids, seen = set(), {}
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for _, line in lines_outside_code(text):
            ids.update(HTML_ID.findall(line))
            m = HEADING.match(line)
            if not m:
                continue
            base = slug(heading_text(m.group(2)))
            k = seen.get(base, 0)
            seen[base] = k + 1
            ids.add(base if k == 0 else f"{base}-{k}")
        cache[path] = ids
    return cache[path]


def check_file(root, path):
    problems = []
    with open(path, encoding="utf-8") as f:
        text = f.read()
    here = os.path.dirname(path)
    rel = os.path.relpath(path, root)
    for n, line in lines_outside_code(text):
        body = strip_code_spans(line)
        targets = [m.group(1) for m in LINK.finditer(body)]
        m = REFDEF.match(body)
        if m:
            targets.append(m.group(1))
        for target in targets:
            target = target.strip("<>")
            if SCHEME.match(target) or target.startswith("//"):
                continue  # a URL: not checked
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(here, file_part)) if file_part else path
            if os.path.relpath(dest, root).startswith(".."):
                problems.append(f"{rel}:{n}: {target}: outside the repository")
                continue
            if not os.path.exists(dest):
                problems.append(f"{rel}:{n}: {target}: no such file")
                continue
            if anchor and dest.endswith(".md") and os.path.isfile(dest):
                if anchor not in anchors(dest):
                    problems.append(f"{rel}:{n}: {target}: no heading #{anchor} in {os.path.relpath(dest, root)}")
    return problems


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    files = [os.path.join(root, "README.md")]
    for d, _, names in os.walk(os.path.join(root, "docs")):
        files += [os.path.join(d, x) for x in sorted(names) if x.endswith(".md")]
    problems = []
    for path in sorted(files):
        problems += check_file(root, path)
    for p in problems:
        print(p)
    print(f"check_links: {len(files)} files, {len(problems)} broken links")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
