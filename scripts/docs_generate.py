#!/usr/bin/env python3
"""Writes the docs site's generated parts that plugin_reference does not: each tool page's options, between its
<!-- help:begin --> and <!-- help:end --> markers, from `rosrun bullet_sim TOOL --help` (TOOL is the page's
name), and the plugin pages' entries in mkdocs.yml's nav, between `# plugins:begin` and `# plugins:end`.

usage: docs_generate.py ROOT   (ROOT holds mkdocs.yml and docs/; the workspace's devel/setup.bash is sourced)"""
import glob
import os
import re
import subprocess
import sys


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


def write_plugin_nav(root):
    config = os.path.join(root, "mkdocs.yml")
    text = open(config).read()
    begin = re.search(r"^( *)# plugins:begin.*$", text, flags=re.M)
    if not begin:
        sys.exit("docs_generate.py: mkdocs.yml has no '# plugins:begin' line")
    indent = begin.group(1)
    pages = sorted(glob.glob(os.path.join(root, "docs", "reference", "plugins", "*.md")))
    entries = ["%s- %s.so: reference/plugins/%s" % (indent, os.path.basename(p)[:-3], os.path.basename(p))
               for p in pages if not p.endswith("/index.md")]
    body = "".join(entry + "\n" for entry in entries) + indent
    open(config, "w").write(replace_between(text, begin.group(0).strip(), "# plugins:end", body, config))


def main():
    root = sys.argv[1]
    write_tool_pages(root)
    write_plugin_nav(root)


if __name__ == "__main__":
    main()
