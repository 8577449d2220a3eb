#!/usr/bin/env python3
"""tests/docs/check_docs.py — what the README and docs/ state about the build, the
package and the CLI, checked against the code. Python 3 standard library only.

    python3 tests/docs/check_docs.py REPO_ROOT commands
    python3 tests/docs/check_docs.py REPO_ROOT dependencies [GENERATED_octrayConfig.cmake]
    python3 tests/docs/check_docs.py REPO_ROOT cli OCTRAY_EXECUTABLE [SCRATCH_DIR]

commands      the README's two commands: the test command is the one .ci/run
              runs; the first is a plain configure, or one with
              -DOCTRAY_ISAS=host (tests, bench and fuzz off
              by default in CMakeLists.txt, on in every tools/check stage)
              whose picture goes under build/ (ignored by git)
dependencies  docs/building.md's dependency table lists exactly the Debian
              packages of tools/install-deps and the find_package /
              pkg_check_modules calls of the build, with their versions, and
              cmake_minimum_required; the find_dependency calls of
              cmake/octrayConfig.cmake.in (and the active ones of the
              generated octrayConfig.cmake) are the ones README.md and
              docs/API.md name
cli           the README's command table lists exactly the subcommands of
              `octray --help`, and for each exactly the options of
              `octray SUB --help`; the first command's render runs (into
              SCRATCH_DIR)

Prints each disagreement; exit 1 if any.
"""
import os
import re
import shlex
import subprocess
import sys

problems = []


def problem(msg):
    problems.append(msg)


def read(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8") as f:
        return f.read()


def section(text, heading):
    """The text under a '## heading' up to the next '## '."""
    m = re.search(r"^## " + re.escape(heading) + r"\s*$", text, re.M)
    if not m:
        problem(f"README.md: no '## {heading}' section")
        return ""
    rest = text[m.end():]
    n = re.search(r"^## ", rest, re.M)
    return rest[: n.start()] if n else rest


def code_blocks(text):
    return re.findall(r"^```[a-z]*\n(.*?)^```", text, re.M | re.S)


def command_lines(block):
    return [line for line in block.splitlines() if line.strip() and not line.lstrip().startswith("#")]


def readme_commands(root):
    blocks = code_blocks(section(read(root, "README.md"), "Two commands"))
    if len(blocks) != 2:
        problem(f"README.md, Two commands: {len(blocks)} code blocks, expected 2")
        return None, None
    one, two = (command_lines(b) for b in blocks)
    if len(one) != 1 or len(two) != 1:
        problem("README.md, Two commands: each block must hold exactly one command line")
        return None, None
    return one[0], two[0]


def check_commands(root):
    first, test = readme_commands(root)
    if first is None:
        return
    ci = command_lines(read(root, ".ci/run"))
    if not ci or ci[-1].strip() != test.strip():
        problem(f".ci/run runs {ci[-1] if ci else '(nothing)'!r}, README's test command is {test!r}")
    steps = [s.strip() for s in first.split("&&")]
    configure = [s for s in steps if s.startswith("cmake -S")]
    # A plain configure, or one that asks for this machine's kernel units only.
    if configure not in (["cmake -S . -B build"], ["cmake -S . -B build -DOCTRAY_ISAS=host"]):
        problem(f"README's first command: expected 'cmake -S . -B build [-DOCTRAY_ISAS=host]', got {configure}")
    render = [s for s in steps if s.startswith("build/octray render")]
    if len(render) != 1:
        problem("README's first command: no 'build/octray render ...' step")
    else:
        args = shlex.split(render[0])
        out = args[args.index("-o") + 1] if "-o" in args else ""
        if not out.startswith("build/"):
            problem(f"README's first command writes {out!r}: its output must go under build/ (ignored by git)")
    gitignore = read(root, ".gitignore").split()
    if "/build*/" not in gitignore and "/build/" not in gitignore:
        problem(".gitignore does not ignore build/")
    cmake = read(root, "CMakeLists.txt")
    for opt in ("OCTRAY_BUILD_TESTS", "OCTRAY_BUILD_BENCH"):
        m = re.search(r"option\(" + opt + r' "[^"]*" (\S+)\)', cmake)
        if not m or m.group(1) != "OFF":
            problem(f"CMakeLists.txt: {opt} must default to OFF (the README's first command builds no tests)")
    m = re.search(r'option\(OCTRAY_FUZZ "[^"]*" (\S+)\)', read(root, "cmake/octraySanitize.cmake"))
    if not m or m.group(1) != "OFF":
        problem("cmake/octraySanitize.cmake: OCTRAY_FUZZ must default to OFF")
    check = read(root, "tools/check")
    if "-DOCTRAY_BUILD_TESTS=ON" not in check or "-DOCTRAY_WERROR=ON" not in check:
        problem("tools/check: must configure with -DOCTRAY_BUILD_TESTS=ON and -DOCTRAY_WERROR=ON")
    configures = re.findall(r"^\s*cmake -S [^\n]*", check, re.M)
    for c in configures:
        if "strict" not in c and "lean" not in c:
            problem(f"tools/check: a stage configures without the tests and -Werror: {c.strip()}")


def table_rows(text):
    # Cells split at unescaped '|' ("simd\|scalar" stays in its cell).
    return [[c.strip() for c in re.split(r"(?<!\\)\|", line.strip()[1:-1])]
            for line in text.splitlines() if line.strip().startswith("|") and not re.match(r"^\|[-| :]+\|$", line.strip())]


def check_dependencies(root, generated):
    doc = read(root, "docs/building.md")
    m = re.search(r"<!-- dependencies: begin -->(.*?)<!-- dependencies: end -->", doc, re.S)
    if not m:
        problem("docs/building.md: no '<!-- dependencies: begin/end -->' table")
        return
    rows = table_rows(m.group(1))[1:]  # without the header
    doc_packages, doc_cmake = set(), set()
    for row in rows:
        if len(row) != 3:
            problem(f"docs/building.md: dependency row with {len(row)} cells: {row}")
            continue
        doc_packages.update(re.findall(r"`([^`]+)`", row[1]))
        doc_cmake.update(re.findall(r"`([^`]+)`", row[2]))

    # tools/install-deps' package list.
    deps = read(root, "tools/install-deps")
    m = re.search(r"packages=\((.*?)\n\)", deps, re.S)
    install = set()
    for line in (m.group(1) if m else "").splitlines():
        install.update(line.split("#")[0].split())
    if install != doc_packages:
        if install - doc_packages:
            problem(f"docs/building.md lacks packages tools/install-deps installs: {sorted(install - doc_packages)}")
        if doc_packages - install:
            problem(f"docs/building.md lists packages tools/install-deps does not install: {sorted(doc_packages - install)}")

    # Every find_package / pkg_check_modules of the build, with its version.
    found = set()
    cmake_files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not d.startswith((".", "build")))
        if "CMakeLists.txt" in names:
            cmake_files.append(os.path.relpath(os.path.join(folder, "CMakeLists.txt"), root))
    for rel in cmake_files:
        for line in read(root, rel).splitlines():
            code = line.split("#")[0]
            for name, ver in re.findall(r"find_package\((\w+)(?:\s+(\d[\d.]*))?", code):
                if name in ("PkgConfig", "octray"):
                    continue
                found.add(f"find_package({name} {ver})" if ver else f"find_package({name})")
            for mod in re.findall(r"pkg_check_modules\(\w+[^)]*?\s(\w+)\)", code):
                found.add(f"pkg_check_modules({mod})")
            for header in re.findall(r"find_path\(\w+\s+([\w.]+)\)", code):
                found.add(f"find_path({header})")
    m = re.search(r"cmake_minimum_required\(VERSION ([\d.]+)\)", read(root, "CMakeLists.txt"))
    if m:
        found.add(f"cmake_minimum_required(VERSION {m.group(1)})")
        if f"CMake ≥ {m.group(1)}" not in doc:
            problem(f"docs/building.md does not say 'CMake ≥ {m.group(1)}'")
    if found != doc_cmake:
        if found - doc_cmake:
            problem(f"docs/building.md lacks what the build looks for: {sorted(found - doc_cmake)}")
        if doc_cmake - found:
            problem(f"docs/building.md lists what the build does not look for: {sorted(doc_cmake - found)}")

    # The installed package's dependencies against the README and docs/API.md.
    template = set(re.findall(r"find_dependency\((\w+)", read(root, "cmake/octrayConfig.cmake.in")))
    for rel in ("README.md", "docs/API.md"):
        named = set(re.findall(r"find_dependency\((\w+)\)", read(root, rel)))
        if named != template:
            problem(f"{rel} names find_dependency of {sorted(named)}; octrayConfig.cmake.in calls {sorted(template)}")
    if generated:
        with open(generated, encoding="utf-8") as f:
            text = f.read()
        # Active calls: those outside every if("FALSE"/"OFF"/"") block of the generated file.
        active, stack = set(), []
        for line in text.splitlines():
            s = line.strip()
            if s.startswith("if("):
                m = re.match(r'if\("([^"]*)"\)', s)
                stack.append(bool(m) and m.group(1).upper() in ("", "FALSE", "OFF", "0", "NO", "N"))
            elif s.startswith("endif") and stack:
                stack.pop()
            else:
                m = re.match(r"find_dependency\((\w+)", s)
                if m and not any(stack):
                    active.add(m.group(1))
        if not active <= template:
            problem(f"{generated} calls find_dependency of {sorted(active - template)}, not in the template")


def help_text(exe, *args):
    r = subprocess.run([exe, *args, "--help"], capture_output=True, text=True)
    if r.returncode != 0:
        problem(f"octray {' '.join(args)} --help exited {r.returncode}")
    return r.stdout


def help_subcommands(text):
    m = re.search(r"^Subcommands:\n((?:  .*\n?)*)", text, re.M)
    return [line.split()[0] for line in (m.group(1) if m else "").splitlines() if line.strip()]


def help_options(text):
    m = re.search(r"^Options:\n((?:  .*\n?)*)", text, re.M)
    opts = set()
    for line in (m.group(1) if m else "").splitlines():
        opts.update(re.findall(r"(?<![\w-])(--[a-z][\w-]*)", line.split("  ")[1] if line.startswith("  ") else line))
    opts.discard("--help")
    return opts


def check_cli(root, exe, scratch):
    readme = read(root, "README.md")
    rows = table_rows(section(readme, "Command line"))[1:]
    table = {}
    for row in rows:
        m = re.match(r"`octray (\w+)([^`]*)`", row[0])
        if not m:
            problem(f"README.md, Command line: row without '`octray SUB ...`': {row[0]}")
            continue
        opts = set(re.findall(r"(?<![\w-])(--[a-z][\w-]*)", m.group(2)))
        for short, long in (("-o", "--output"),):
            if re.search(r"(?<![\w-])" + short + r"\b", m.group(2)):
                opts.add(long)
        table[m.group(1)] = opts
    subs = help_subcommands(help_text(exe))
    if not subs:
        problem("octray --help lists no subcommands")
    if sorted(table) != sorted(subs):
        problem(f"README's command table lists {sorted(table)}; octray --help lists {sorted(subs)}")
    for sub in subs:
        opts = help_options(help_text(exe, sub))
        if sub in table and table[sub] != opts:
            problem(f"README's row for 'octray {sub}' has options {sorted(table[sub])}; "
                    f"'octray {sub} --help' lists {sorted(opts)}")
    # The first command's render, as written, into the scratch folder.
    first, _ = readme_commands(root)
    if first and scratch:
        step = [s.strip() for s in first.split("&&") if s.strip().startswith("build/octray render")]
        if step:
            args = shlex.split(step[0])[1:]
            out = os.path.join(scratch, "readme_command_1.png")
            args[args.index("-o") + 1] = out
            r = subprocess.run([exe, *args], cwd=root, capture_output=True, text=True)
            if r.returncode != 0 or not os.path.exists(out):
                problem(f"README's first command's render failed ({r.returncode}): {r.stderr.strip()}")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    root, what = sys.argv[1], sys.argv[2]
    if what == "commands":
        check_commands(root)
    elif what == "dependencies":
        check_dependencies(root, sys.argv[3] if len(sys.argv) > 3 else None)
    elif what == "cli":
        check_cli(root, sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None)
    else:
        sys.exit(f"check_docs: unknown check {what!r}\n{__doc__}")
    for p in problems:
        print(p)
    print(f"check_docs {what}: {len(problems)} disagreements")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
