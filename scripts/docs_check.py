#!/usr/bin/env python3
"""Checks the docs site beyond what `mkdocs build --strict` 1.4 checks: every page under docs/ is in mkdocs.yml's
nav; every link to an #anchor, on the built site and in the README, lands on a heading that exists there and
on GitHub (MkDocs and GitHub make a heading's id alike for our headings; a link passes only when both agree);
and no list or text starts on the line after a paragraph's or a code block's end (GitHub shows them apart,
MkDocs runs them together).

usage: docs_check.py REPO SITE_DIR   (SITE_DIR: what `mkdocs build` wrote from REPO/mkdocs.yml)
Exit status: 0 clean, 1 problems (each on a line of its own)."""
import glob
import html.parser
import os
import re
import sys
import urllib.parse

import yaml


def nav_pages(nav):
    """The docs/-relative paths of the pages a nav lists."""
    pages = []
    for item in nav:
        value = list(item.values())[0] if isinstance(item, dict) else item
        if isinstance(value, list):
            pages += nav_pages(value)
        elif not re.match(r"\w+://", value):
            pages.append(value)
    return pages


def check_nav(repo):
    with open(os.path.join(repo, "mkdocs.yml")) as f:
        config = yaml.safe_load(f)
    docs = os.path.join(repo, config.get("docs_dir", "docs"))
    listed = set(nav_pages(config["nav"]))
    present = {os.path.relpath(p, docs) for p in glob.glob(os.path.join(docs, "**", "*.md"), recursive=True)}
    return (["docs/%s: not in mkdocs.yml's nav" % page for page in sorted(present - listed)] +
            ["mkdocs.yml's nav lists %s, which docs/ lacks" % page for page in sorted(listed - present)])


class Links(html.parser.HTMLParser):
    """The ids and the hrefs of one HTML page."""

    def __init__(self):
        super().__init__()
        self.ids, self.hrefs = set(), []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("href"):
            self.hrefs.append(attrs["href"])


def github_slug(heading):
    """GitHub's id for a Markdown heading: lower case, punctuation but - and _ dropped, spaces as -."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text
    text = re.sub(r"[^\w\- ]", "", text.lower())
    return text.replace(" ", "-")


def markdown_slugs(path):
    """The GitHub ids of a Markdown file's headings (outside code blocks), with -1, -2 for repeats."""
    slugs, code = set(), False
    for line in open(path):
        if line.startswith("```"):
            code = not code
        match = None if code else re.match(r"#{1,6} (.*)", line)
        if match:
            slug = github_slug(match.group(1).strip())
            n, unique = 0, slug
            while unique in slugs:
                n += 1
                unique = "%s-%d" % (slug, n)
            slugs.add(unique)
    return slugs


def page_of_html(site, html_path):
    """The Markdown source (docs/-relative) of a built page: x/index.html <- x.md (or x/index.md)."""
    rel = os.path.relpath(html_path, site)
    if rel == "index.html":
        return "index.md"
    folder = os.path.dirname(rel)
    return folder + ".md" if not folder.endswith("/index") else folder


def check_site_anchors(repo, site):
    problems, pages = [], {}
    for path in glob.glob(os.path.join(site, "**", "*.html"), recursive=True):
        if os.path.relpath(path, site).startswith(("assets", "search")) or path.endswith("404.html"):
            continue
        parser = Links()
        parser.feed(open(path, encoding="utf-8").read())
        pages[os.path.normpath(path)] = parser
    for path, parser in sorted(pages.items()):
        for href in parser.hrefs:
            url = urllib.parse.urlsplit(href)
            if url.scheme or url.netloc or not url.fragment or href.startswith("/"):
                continue
            target = os.path.normpath(os.path.join(os.path.dirname(path), urllib.parse.unquote(url.path)))
            if os.path.isdir(target) or not url.path:
                target = os.path.join(target, "index.html") if url.path else path
            fragment = urllib.parse.unquote(url.fragment)
            if target not in pages:
                problems.append("%s: link %s to a page that is not built" % (page_of_html(site, path), href))
            elif fragment not in pages[target].ids:
                problems.append("%s: link %s: no heading %s there" % (page_of_html(site, path), href, fragment))
            else:
                source = os.path.join(repo, "docs", page_of_html(site, target))
                if os.path.exists(source) and fragment not in markdown_slugs(source) and \
                        not fragment.startswith("__"):
                    problems.append("%s: link %s: GitHub names that heading otherwise" %
                                    (page_of_html(site, path), href))
    return sorted(set(problems))


def check_readme(repo):
    """The README's links into docs/: the file exists, and its anchor is a heading there."""
    problems = []
    text = open(os.path.join(repo, "README.md")).read()
    for target in re.findall(r"\]\((docs/[^)\s]+)\)", text):
        path, _, fragment = target.partition("#")
        full = os.path.join(repo, path)
        if not os.path.exists(full):
            problems.append("README.md: link to %s, which does not exist" % path)
        elif fragment and full.endswith(".md") and fragment not in markdown_slugs(full):
            problems.append("README.md: link %s: no heading %s there" % (target, fragment))
    return problems


def check_lists(repo):
    """Pages' blocks that GitHub and MkDocs read alike: a blank line between a paragraph and its list, and after
    a code block."""
    problems = []
    for path in sorted(glob.glob(os.path.join(repo, "docs", "**", "*.md"), recursive=True)):
        previous, code, closing = "", False, False
        for number, line in enumerate(open(path), 1):
            if line.strip().startswith("```"):
                code = not code
            paragraph = previous.strip() and not re.match(r"\s|#|[-*+] |\d+\. |\||```|<!--|>", previous)
            if not code and re.match(r"([-*+]|\d+\.) ", line) and paragraph:
                problems.append("%s:%d: a list right after a paragraph line: put a blank line before it" %
                                (os.path.relpath(path, repo), number))
            if closing and line.strip() and not line.startswith("<!--"):
                problems.append("%s:%d: text right after a code block: put a blank line before it" %
                                (os.path.relpath(path, repo), number))
            closing = line.strip().startswith("```") and not code
            previous = line
    return problems


def main():
    repo, site = sys.argv[1], sys.argv[2]
    problems = check_nav(repo) + check_site_anchors(repo, site) + check_readme(repo) + check_lists(repo)
    for problem in problems:
        print(problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
