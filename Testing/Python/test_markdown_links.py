#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Every link and cited path in the project's Markdown files and source headers exists.

Checks, from the repository root (found from this file's path, two levels up):
  - in every Markdown file of the checkout (tracked or new, not ignored; build*/ and .git are
    skipped): relative links and images ``[text](target)`` point at an existing file or folder,
    and a ``#fragment`` into a Markdown file names one of its headings (GitHub's anchors);
  - in the same files: backticked tokens that look like repository paths (starting with
    Filters/, Plugin/, Testing/, Data/, docs/, .ci/ or CMake/; a command's first word counts,
    wildcards are globbed) exist;
  - in the source headers (Filters/**/*.h) and Plugin/ShapeDiameter.xml: every cited
    ``docs/....md`` page and ``README.md`` path exists.
Code blocks are not checked. Each failure is printed as ``file:line: reason``; the exit status
is 1 when there is any. Needs the Python standard library only (runs under pvpython or python3).
"""

import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PATH_PREFIXES = ("Filters/", "Plugin/", "Testing/", "Data/", "docs/", ".ci/", "CMake/")

LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
FENCE = re.compile(r"^\s{0,3}(```|~~~)")
HEADING = re.compile(r"^\s{0,3}#{1,6}\s+(.*?)\s*#*\s*$")
HEADER_CITATION = re.compile(r"(?<![\w/.-])((?:[\w.-]+/)*(?:docs/[\w.-]+\.md|README\.md))")


def markdown_files():
    """Markdown files of the checkout: git's tracked and untracked-not-ignored ones, else a walk."""
    try:
        listed = subprocess.run(
            ["git", "-C", ROOT, "ls-files", "--cached", "--others", "--exclude-standard", "*.md"],
            check=True, capture_output=True, text=True).stdout.split("\n")
        files = sorted({path for path in listed if path and os.path.isfile(os.path.join(ROOT, path))})
        if files:
            return files
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for directory, subdirectories, names in os.walk(ROOT):
        subdirectories[:] = sorted(d for d in subdirectories
                                   if d != ".git" and not (directory == ROOT and d.startswith("build")))
        files += [os.path.relpath(os.path.join(directory, name), ROOT)
                  for name in sorted(names) if name.endswith(".md")]
    return files


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|__", "", heading)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link keeps its text
    text = text.strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def prose_lines(path):
    """(line number, text) of the lines outside fenced code blocks."""
    with open(os.path.join(ROOT, path), encoding="utf-8") as stream:
        lines = stream.read().split("\n")
    fenced = False
    for number, line in enumerate(lines, start=1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield number, line


_anchor_cache = {}


def anchors(path):
    if path not in _anchor_cache:
        found = set()
        counts = {}
        for _, line in prose_lines(path):
            match = HEADING.match(line)
            if match:
                base = slug(match.group(1))
                n = counts.get(base, 0)
                counts[base] = n + 1
                found.add(base if n == 0 else "%s-%d" % (base, n))
        _anchor_cache[path] = found
    return _anchor_cache[path]


def repository_path_exists(token):
    if any(c in token for c in "*?["):
        return bool(glob.glob(os.path.join(ROOT, token)))
    return os.path.exists(os.path.join(ROOT, token))


def check_link(source, number, target, failures):
    if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("//"):
        return  # http:, https:, mailto: ...
    file_part, _, fragment = target.partition("#")
    if file_part:
        resolved = os.path.normpath(os.path.join(os.path.dirname(source), file_part))
        if resolved.startswith(".."):
            failures.append("%s:%d: link '%s' leaves the repository" % (source, number, target))
            return
        if not os.path.exists(os.path.join(ROOT, resolved)):
            failures.append("%s:%d: dead link '%s'" % (source, number, target))
            return
    else:
        resolved = source
    if fragment and resolved.endswith(".md") and fragment not in anchors(resolved):
        failures.append("%s:%d: link '%s': no heading with anchor '#%s' in %s"
                        % (source, number, target, fragment, resolved))


def check_code_span(source, number, span, failures):
    words = span.strip().split()
    if not words:
        return
    token = words[0]
    if token.startswith("./"):
        token = token[2:]
    token = token.rstrip(".,;:)")
    if token.startswith(PATH_PREFIXES) and not repository_path_exists(token):
        failures.append("%s:%d: cited path '%s' does not exist" % (source, number, token))


def check_markdown(path, failures):
    for number, line in prose_lines(path):
        for match in CODE_SPAN.finditer(line):
            check_code_span(path, number, match.group(2), failures)
        prose = CODE_SPAN.sub("", line)
        for match in LINK.finditer(prose):
            check_link(path, number, match.group(1), failures)
        match = REFERENCE.match(prose)
        if match:
            check_link(path, number, match.group(1), failures)


def source_files():
    files = sorted(os.path.relpath(path, ROOT)
                   for path in glob.glob(os.path.join(ROOT, "Filters", "**", "*.h"), recursive=True))
    return files + ["Plugin/ShapeDiameter.xml"]


def check_source(path, failures):
    with open(os.path.join(ROOT, path), encoding="utf-8") as stream:
        for number, line in enumerate(stream, start=1):
            for match in HEADER_CITATION.finditer(line):
                cited = match.group(1)
                if not os.path.exists(os.path.join(ROOT, cited)):
                    failures.append("%s:%d: cited '%s' does not exist" % (path, number, cited))


def main():
    failures = []
    documents = markdown_files()
    for path in documents:
        check_markdown(path, failures)
    sources = source_files()
    for path in sources:
        check_source(path, failures)
    for failure in failures:
        print(failure)
    print("%d Markdown files, %d source files checked: %d failure(s)"
          % (len(documents), len(sources), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
