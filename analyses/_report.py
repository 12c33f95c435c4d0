"""Write one marked section of a Markdown report, keeping the other sections."""
import os
import re

START = "<!-- section:{name} -->"
END = "<!-- /section:{name} -->"


def write_section(path, name, text):
    """Replace (or append) the section ``name`` of ``path`` atomically."""
    start, end = START.format(name=name), END.format(name=name)
    block = f"{start}\n{text.rstrip()}\n{end}\n"
    old = path.read_text() if path.exists() else ""
    pat = re.compile(re.escape(start) + r".*?" + re.escape(end) + r"\n?", re.S)
    new = pat.sub(lambda m: block, old) if pat.search(old) else (
        old + ("\n" if old and not old.endswith("\n") else "") + block)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(new)
    os.replace(tmp, path)
