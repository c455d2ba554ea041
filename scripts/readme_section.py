"""Rewrites a generated section of a page (docs/performance.md, README.md): the lines between
<!-- NAME:begin --> and <!-- NAME:end -->."""
import re


def write_section(readme, name, lines, place):
    """Puts `lines` between the NAME markers in the file `readme`. A page without them gets the marked
    section where place(text, section) puts it."""
    begin, end = "<!-- %s:begin -->" % name, "<!-- %s:end -->" % name
    section = begin + "\n" + "\n".join(lines) + "\n" + end
    text = open(readme).read()  # read right before writing: others edit the page too
    if begin in text:
        text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: section, text, flags=re.S)
    else:
        text = place(text, section)
    open(readme, "w").write(text)


def met(ok):
    """A table's "met" column: yes, or a bold no."""
    return "yes" if ok else "**no**"
