#!/usr/bin/env python3
"""Writes the docs site's generated parts that plugin_reference does not: each tool page's options, between its
<!-- help:begin --> and <!-- help:end --> markers, from `rosrun bullet_sim TOOL --help` (TOOL is the page's
name); a page per launch file of bullet_sim and bullet_sim_bringup (docs/reference/launch/NAME.md: its comment
and its arguments, with their defaults and the comments on their lines); and the entries of the plugin and
launch file pages in mkdocs.yml's nav, between `# plugins:begin` and `# plugins:end` (`# launch:...`).

usage: docs_generate.py ROOT   (ROOT holds mkdocs.yml and docs/; the workspace's devel/setup.bash is sourced)"""
import glob
import html
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET


def tool_help(tool):
    """What `tool --help` prints, the same on every terminal."""
    env = dict(os.environ, COLUMNS="110")  # argparse wraps to the terminal's width
    done = subprocess.run(["rosrun", "bullet_sim", tool, "--help"], env=env, capture_output=True, text=True,
                          timeout=60)
    if done.returncode != 0:
        sys.exit("docs_generate.py: %s --help failed (%d): %s" % (tool, done.returncode, done.stderr.strip()))
    return done.stdout.rstrip("\n")


def replace_between(text, begin, end, body, where):
    pattern = re.escape(begin) + ".*?" + re.escape(end)
    if not re.search(pattern, text, flags=re.S):
        sys.exit("docs_generate.py: %s has no %s ... %s" % (where, begin, end))
    return re.sub(pattern, lambda _: begin + "\n" + body + end, text, count=1, flags=re.S)


def write_tool_pages(root):
    for page in sorted(glob.glob(os.path.join(root, "docs", "reference", "tools", "*.md"))):
        tool = os.path.basename(page)[:-3]
        text = open(page).read()
        block = "```text\n" + tool_help(tool) + "\n```\n"
        open(page, "w").write(replace_between(text, "<!-- help:begin -->", "<!-- help:end -->", block, page))


REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCH_FOLDERS = [("bullet_sim", "bullet_sim/launch"), ("bullet_sim_bringup", "bullet_sim_bringup/launch")]
ARG = re.compile(r'^  <arg name="([^"]+)"(?: default="([^"]*)")?\s*/>\s*(?:<!--\s*(.*?)\s*-->)?\s*$')


def cell(text):
    """Text as a Markdown table cell that GitHub and MkDocs show as written."""
    return html.escape(text, quote=False).replace("|", "\\|")


def launch_page(package, path):
    """A launch file's page: its leading comment, how to launch it, and its arguments (the <launch>'s own
    <arg>s with a default, or none: required; an <arg value=...> is fixed and left out)."""
    text = open(path).read()
    comment = re.match(r"\s*<!--(.*?)-->", text, flags=re.S)
    name = os.path.basename(path)
    lines = ["<!-- Written by scripts/docs.sh from %s/%s: edit that file, not this page. -->" %
             (os.path.relpath(os.path.dirname(path), REPO), name),
             "# `%s %s`" % (package, name), ""]
    if comment:
        lines += [cell(" ".join(comment.group(1).split())), ""]
    lines += ["```bash", "roslaunch %s %s [ARG:=VALUE ...]" % (package, name), "```", "",
              "| argument | default | what it is |", "|---|---|---|"]
    shown = set()
    for line in text.split("\n"):
        arg = ARG.match(line)
        if arg:
            default = "(required)" if arg.group(2) is None else "`%s`" % arg.group(2) if arg.group(2) else '`""`'
            lines.append("| `%s` | %s | %s |" % (arg.group(1), default, cell(arg.group(3) or "")))
            shown.add(arg.group(1))
    arguments = {arg.get("name") for arg in ET.parse(path).getroot().findall("arg") if "value" not in arg.attrib}
    if arguments != shown:
        sys.exit("docs_generate.py: %s: write each of its arguments %s on one line, as <arg name=... default=.../>"
                 " indented by two spaces" % (path, sorted(arguments - shown)))
    return "\n".join(lines) + "\n"


def write_launch_pages(root):
    folder = os.path.join(root, "docs", "reference", "launch")
    os.makedirs(folder, exist_ok=True)
    for package, launch_dir in LAUNCH_FOLDERS:
        for path in sorted(glob.glob(os.path.join(REPO, launch_dir, "*.launch"))):
            page = os.path.join(folder, os.path.basename(path)[:-len(".launch")] + ".md")
            open(page, "w").write(launch_page(package, path))


def write_nav(root, marker, folder, title):
    """The nav entries between `# MARKER:begin` and `# MARKER:end`: a page of docs/FOLDER each (but index.md),
    titled title(its name without .md)."""
    config = os.path.join(root, "mkdocs.yml")
    text = open(config).read()
    begin = re.search(r"^( *)# %s:begin.*$" % marker, text, flags=re.M)
    if not begin:
        sys.exit("docs_generate.py: mkdocs.yml has no '# %s:begin' line" % marker)
    indent = begin.group(1)
    pages = sorted(os.path.basename(p) for p in glob.glob(os.path.join(root, "docs", folder, "*.md")))
    entries = ["%s- %s: %s/%s" % (indent, title(p[:-3]), folder, p) for p in pages if p != "index.md"]
    body = "".join(entry + "\n" for entry in entries) + indent
    open(config, "w").write(replace_between(text, begin.group(0).strip(), "# %s:end" % marker, body, config))


def main():
    root = sys.argv[1]
    write_tool_pages(root)
    write_launch_pages(root)
    write_nav(root, "plugins", "reference/plugins", lambda name: name + ".so")
    write_nav(root, "launch", "reference/launch", lambda name: name + ".launch")


if __name__ == "__main__":
    main()
