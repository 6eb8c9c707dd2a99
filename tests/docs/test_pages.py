"""The documentation pages run as written.

For every Markdown page under docs/ (docs/**/*.md, build outputs aside):

- its ```python blocks run in order in one namespace per page, as a reader pasting them one
  after the other would, in a scratch directory that holds a copy of docs/machines (the pages
  name those files as docs/machines/…, as from the root of a checkout) and every file the
  page shows under a name (a ```{code-block} with ``:caption: NAME`` is written to NAME
  first);
- its TOML blocks are TOML, and those that describe a machine load as one;
- its `multicrank …` shell commands name real commands and options with valid values
  (parsed by the CLI itself, not run);
- its figures (matplotlib's plot directive, in ```{eval-rst} blocks) draw, each in a fresh
  namespace from the page's own directory, as the Sphinx build does.

A page whose blocks need an optional package says so in a MyST comment line,
``% docs-test: needs dask, distributed``; without the package its blocks are skipped.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import shutil
import sys
import textwrap
import tomllib
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path

import click
import pytest

import multicrank as mc

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
BUILT = {"_build", "auto_examples", "generated"}
PAGES = sorted(page for page in DOCS.rglob("*.md") if not BUILT & set(page.relative_to(DOCS).parts))

# A fenced block, at the start of a line or indented in a list item: ```python, ```toml,
# ```bash, or a directive ```{code-block} LANG with options (":caption: NAME") before an
# empty line.
FENCE = re.compile(r"^([ \t]*)```(?:\{code-block\}\s*)?(\w+)[ \t]*\n(.*?)^\1```[ \t]*$", re.M | re.S)
OPTION = re.compile(r"\A((?::[\w-]+:.*\n)+)\n", re.M)
# A figure: ```{eval-rst} holding one ".. plot::" directive with options and inline code.
PLOT = re.compile(r"^```\{eval-rst\}\n\.\. plot::\n(?:[ \t]+:[^\n]*\n)*\n(.*?)^```[ \t]*$", re.M | re.S)


@dataclass
class Block:
    language: str
    code: str
    caption: str | None
    line: int


def blocks(page: Path) -> list[Block]:
    text = page.read_text(encoding="utf-8")
    found = []
    for match in FENCE.finditer(text):
        body, caption = textwrap.dedent(match[3]), None  # a block in a list item is indented
        options = OPTION.match(body)
        if options:
            body = body[options.end() :]
            named = re.search(r"^:caption:\s*(\S+)\s*$", options[1], re.M)
            caption = named[1] if named else None
        found.append(Block(match[2], body, caption, text.count("\n", 0, match.start()) + 1))
    return found


def needs(page: Path) -> list[str]:
    text = page.read_text(encoding="utf-8")
    return [name.strip() for line in re.findall(r"^% docs-test: needs (.+)$", text, re.M) for name in line.split(",")]


def skip_without_extras(page: Path) -> None:
    missing = [name for name in needs(page) if importlib.util.find_spec(name) is None]
    if missing:
        pytest.skip(f"{page.relative_to(DOCS)} needs {', '.join(missing)}")


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A directory like the root of a checkout: docs/machines copied in, the cwd."""
    shutil.copytree(DOCS / "machines", tmp_path / "docs" / "machines")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


def write_named_files(page: Path, where: Path) -> None:
    for block in blocks(page):
        if block.caption:
            (where / block.caption).write_text(block.code, encoding="utf-8")


def page_id(page: Path) -> str:
    return str(page.relative_to(DOCS))


def test_the_pages_are_found():
    names = {page_id(page) for page in PAGES}
    assert {"getting-started.md", "theory.md", "machine-files.md", "howto/index.md"} <= names
    assert sum(block.language == "python" for page in PAGES for block in blocks(page)) >= 20
    assert sum(len(figures(page)) for page in PAGES) >= 9


# dask's to_parquet and read_parquet call DataFrame.set_index/reset_index with inplace=True,
# which pandas >= 3.1 deprecates: not ours to fix (in a worker process it is only printed; the
# cluster of the sweeps guide runs in this process).
@pytest.mark.filterwarnings("ignore:The inplace keyword in DataFrame:Warning")
@pytest.mark.parametrize("page", [p for p in PAGES if any(b.language == "python" for b in blocks(p))], ids=page_id)
def test_python_blocks_run(page, scratch):
    skip_without_extras(page)
    write_named_files(page, scratch)
    namespace: dict = {"__name__": "__main__"}
    try:
        for block in blocks(page):
            if block.language != "python":
                continue
            where = f"{page_id(page)}, line {block.line}"
            try:
                exec(compile(block.code, where, "exec"), namespace)
            except Exception as error:  # pragma: no cover - the message is the point
                pytest.fail(f"the python block of {where} fails: {error!r}\n{block.code}")
    finally:
        if "matplotlib.pyplot" in sys.modules:  # a page that draws leaves no figures open
            sys.modules["matplotlib.pyplot"].close("all")


@pytest.mark.parametrize("page", [p for p in PAGES if any(b.language == "toml" for b in blocks(p))], ids=page_id)
def test_toml_blocks_are_machine_files(page, scratch):
    for number, block in enumerate(b for b in blocks(page) if b.language == "toml"):
        where = f"{page_id(page)}, line {block.line}"
        try:
            table = tomllib.loads(block.code)
        except tomllib.TOMLDecodeError as error:
            pytest.fail(f"the TOML block of {where} is not TOML: {error}")
        if "cylinder" in table:
            # Next to the example files, so that a CSV named relative to the file is found.
            path = scratch / "docs" / "machines" / f"page-block-{number}.toml"
            path.write_text(block.code, encoding="utf-8")
            try:
                mc.Machine.from_toml(path)
            except mc.MechanismError as error:  # pragma: no cover - the message is the point
                pytest.fail(f"the machine file of {where} does not load: {error}")


def shell_commands(page: Path) -> list[tuple[int, list[str]]]:
    commands = []
    for block in blocks(page):
        if block.language not in ("bash", "console", "shell"):
            continue
        for offset, line in enumerate(block.code.replace("\\\n", " ").splitlines()):
            words = shlex.split(line, comments=True)
            if "multicrank" in words:
                start = words.index("multicrank")  # "pip install … && multicrank report"
                commands.append((block.line + 1 + offset, words[start + 1 :]))
    return commands


@pytest.mark.parametrize("page", [p for p in PAGES if shell_commands(p)], ids=page_id)
def test_shell_commands_parse(page, scratch):
    from multicrank.cli import main

    write_named_files(page, scratch)
    for line, args in shell_commands(page):
        where = f"{page_id(page)}, line {line}: multicrank {shlex.join(args)}"
        assert args, where
        command = main.commands.get(args[0])
        assert command is not None, f"{where}: no such command"
        name, rest = args[0], args[1:]
        try:
            # A group's own options, then its subcommand's ("multicrank sweep motion …"),
            # each parsed as the command line would.
            while isinstance(command, click.Group) and (sub := next((w for w in rest if w in command.commands), None)):
                index = rest.index(sub)
                command.make_context(name, rest[:index])
                command, name, rest = command.commands[sub], sub, rest[index + 1 :]
            command.make_context(name, rest)
        except Exception as error:  # click.UsageError and the --machine loader's errors
            pytest.fail(f"{where}: {error}")


def figures(page: Path) -> list[str]:
    return [textwrap.dedent(code) for code in PLOT.findall(page.read_text(encoding="utf-8"))]


@pytest.mark.parametrize("page", [p for p in PAGES if figures(p)], ids=page_id)
def test_figures_draw(page, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(page.parent)  # where the plot directive runs a page's code
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for number, code in enumerate(figures(page), start=1):
        where = f"{page_id(page)}, figure {number}"
        try:
            exec(compile(code, where, "exec"), {"__name__": "__main__"})
            assert plt.get_fignums(), f"{where} draws nothing"
        except Exception as error:  # pragma: no cover - the message is the point
            pytest.fail(f"{where} fails: {error!r}\n{code}")
        finally:
            plt.close("all")


# -- the built site ----------------------------------------------------------------------------
# scripts/test builds the site (scripts/docs) after its main test run, then runs these tests with
# MULTICRANK_DOCS_SITE=docs/_build/html; without it they are skipped, so that a site left by an
# older checkout is not what is tested.

# A URL with a scheme or a protocol-relative one ("//cdn…"): anything not in the site itself.
REMOTE = re.compile(r"^\s*(?:[a-z][a-z0-9+.-]*:)?//", re.I)


def built_site() -> Path:
    where = os.environ.get("MULTICRANK_DOCS_SITE")
    if not where:
        pytest.skip("the built site: scripts/test runs this after building it, with MULTICRANK_DOCS_SITE set")
    site = ROOT / where  # an absolute path stays itself
    assert (site / "index.html").is_file(), f"MULTICRANK_DOCS_SITE={where}: no built site there (run scripts/docs)"
    return site


class _Scripts(HTMLParser):
    """The src of every <script> of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.sources: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        source = dict(attrs).get("src")
        if tag == "script" and source:
            self.sources.append(source)


def scripts(html: str) -> list[str]:
    parser = _Scripts()
    parser.feed(html)
    return parser.sources


def test_built_site_loads_no_remote_script():
    site = built_site()
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 20
    for page in pages:
        html = page.read_text(encoding="utf-8")
        remote = [source for source in scripts(html) if REMOTE.match(source)]
        assert not remote, f"{page.relative_to(site)} loads scripts from the network: {remote}"
        assert "//cdn" not in html.lower(), f"{page.relative_to(site)} names a CDN"


def test_built_site_serves_its_maths():
    """Every page with maths loads MathJax from the site's own _static, which holds its fonts:
    the theory page renders offline."""
    site = built_site()
    static = (site / "_static").resolve()
    fonts = sorted((static / "mathjax" / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))
    assert fonts, "MathJax's CHTML fonts are not in _static/mathjax"
    with_maths = [page for page in sorted(site.rglob("*.html")) if 'class="math' in page.read_text(encoding="utf-8")]
    assert site / "theory.html" in with_maths
    for page in with_maths:
        mathjax = [src for src in scripts(page.read_text(encoding="utf-8")) if "mathjax" in src.lower()]
        assert mathjax, f"{page.relative_to(site)} shows maths but loads no MathJax"
        for source in mathjax:
            path = (page.parent / source.split("?")[0]).resolve()
            assert path.is_relative_to(static) and path.is_file(), (
                f"{page.relative_to(site)}: {source} is not in _static"
            )
            assert "MathJax" in path.read_text(encoding="utf-8")
