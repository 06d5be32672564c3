"""The documentation site: built with warnings as errors and its notebooks executed, then read in headless Chromium.

The build is the README's command (``python -m sphinx -W --keep-going -b html docs OUT``). A few rendered pages
are then served on 127.0.0.1 and opened in Debian's Chromium through the DevTools protocol: the math is typeset
by the local MathJax (no error nodes), every image has loaded, the console has no error, and no request goes to
any address but the loopback server. Screenshots go to ``$FORCENET_DOCS_SCREENSHOTS`` when it is set.

The static checks (no issue numbers on the user pages, no script, style or image from the network in the built
HTML) need no browser. Without Chromium the browser test is skipped with the reason, except on CI
(``CI=true``), where it fails.
"""

from __future__ import annotations

import asyncio
import functools
import http.server
import json
import os
import re
import runpy
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"

# the user pages (not the API pages, which are generated from docstrings, nor notes/)
USER_PAGES = sorted([*DOCS.rglob("*.md"), *DOCS.rglob("*.rst"), ROOT / "CHANGELOG.md"])
USER_PAGES = [p for p in USER_PAGES if "_build" not in p.parts and "generated" not in p.parts]
ISSUE = re.compile(r"\bissues?\s*#?\d+|(?<![\w&/])#\d+\b", re.IGNORECASE)


def test_no_user_page_speaks_of_issue_numbers():
    assert len(USER_PAGES) > 20
    found = [f"{p.relative_to(ROOT)}: {m.group(0)!r}" for p in USER_PAGES for m in ISSUE.finditer(p.read_text())]
    assert not found, found


def test_the_issue_pattern_sees_issue_numbers():
    """A control: the pattern finds what it must, and not an equation number or an HTML entity."""
    assert ISSUE.search("as in issue 25") and ISSUE.search("see #42") and ISSUE.search("Issues 3, 4")
    assert not ISSUE.search("Eq. (4.63)") and not ISSUE.search("&#39;") and not ISSUE.search("page.html#12")


def test_the_readme_gives_the_documentation_command_and_ci_runs_the_docs_test():
    command = "python -m pip install '.[docs]' && python -m sphinx -W --keep-going -b html docs docs/_build/html"
    assert command in (ROOT / "README.md").read_text()
    ci = (ROOT / ".ci" / "run").read_text()
    assert "python -m pip install '.[test]' && python -m pytest" in ci
    assert "tests/test_docs.py" in ci and "chromium" in ci


# ------------------------------------------------------------------------------------------------ the build


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site built by the README's command into a temporary folder (warnings are errors)."""
    out = tmp_path_factory.mktemp("site") / "html"
    start = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", str(DOCS), str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=1200, check=False)
    seconds = time.monotonic() - start
    assert proc.returncode == 0, f"the build failed ({seconds:.0f} s):\n{proc.stderr[-6000:]}"
    print(f"documentation built in {seconds:.0f} s")
    return out


TUTORIALS = ["exact_tables", "testing_monte_carlo", "symbolic_session", "force_distributions", "chicken_wire",
             "distributed"]


@pytest.mark.slow
def test_the_tutorials_carry_executed_output_and_figures(site):
    with_output, with_figures = [], []
    for name in TUTORIALS:
        html = (site / "tutorials" / f"{name}.html").read_text()
        if html.count('class="cell_output') >= 3:
            with_output.append(name)
        if re.search(r'<img[^>]+src="\.\./_images/[^"]+\.png"', html):
            with_figures.append(name)
    assert len(with_output) >= 5, with_output
    assert len(with_figures) >= 3, with_figures
    for name in with_figures:  # the figures exist and are PNGs
        html = (site / "tutorials" / f"{name}.html").read_text()
        for src in re.findall(r'<img[^>]+src="\.\./(_images/[^"]+\.png)"', html):
            assert (site / src).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_every_public_name_has_its_api_page_with_an_example(site):
    pages = {p.stem: p for p in (site / "api" / "generated").glob("*.html")}
    for name in ["forcenet.exact.mean_W", "forcenet.exact.count", "forcenet.exact.triangle.density",
                 "forcenet.exact.triangle.free_fermion.mean_W", "forcenet.numeric.triangle.ExactSampler",
                 "forcenet.numeric.triangle.TriangleMetropolis", "forcenet.numeric.chicken_wire.isotropic.entropy",
                 "forcenet.testing.assert_agrees", "forcenet.testing.compare", "forcenet.ForcenetError",
                 "forcenet.ArgumentError"]:
        assert name in pages, name
    functions = [p for n, p in pages.items() if not n.split(".")[-1][0].isupper()]
    assert len(functions) > 40
    missing = [p.stem for p in functions if "Examples" not in p.read_text()]  # none is excused (docs/conf.py)
    assert not missing, f"API pages without an example: {missing}"


REMOTE = re.compile(r"""(?:src|href)\s*=\s*["']((?:https?:)?//[^"']+)["']""", re.IGNORECASE)


@pytest.mark.slow
def test_the_built_site_loads_nothing_from_the_network(site):
    """No script, stylesheet, image or font is taken from another host (links to read are not loads)."""
    offenders = []
    for page in site.rglob("*.html"):
        html = page.read_text(errors="replace")
        for tag in re.findall(r"<(?:script|link|img|iframe|source|video|audio)\b[^>]*>", html, re.IGNORECASE):
            if re.search(r'\brel\s*=\s*["\']?(?:canonical|author|next|prev|index|search|copyright)', tag):
                continue
            offenders += [f"{page.relative_to(site)}: {url}" for url in REMOTE.findall(tag)]
    for sheet in site.rglob("*.css"):
        offenders += [f"{sheet.relative_to(site)}: {url}" for url in
                      re.findall(r"url\(\s*['\"]?((?:https?:)?//[^)'\"]+)", sheet.read_text(errors="replace"))]
        offenders += [f"{sheet.relative_to(site)}: @import {url}" for url in
                      re.findall(r"@import\s+['\"]((?:https?:)?//[^'\"]+)", sheet.read_text(errors="replace"))]
    assert not offenders, offenders[:20]
    assert (site / "_static" / "mathjax" / "tex-chtml.js").is_file()  # the local MathJax
    assert "mathjax/tex-chtml.js" in (site / "index.html").read_text()


@pytest.mark.slow
def test_no_rendered_page_speaks_of_issue_numbers(site):
    """The API pages too (they come from docstrings)."""
    found = []
    for page in site.rglob("*.html"):
        text = re.sub(r"<[^>]+>", " ", page.read_text(errors="replace"))
        found += [f"{page.relative_to(site)}: {m.group(0)!r}" for m in re.finditer(r"\bissues?\s+\d+", text, re.I)]
    assert not found, found[:20]


# ------------------------------------------------------------------------------------------------ the browser


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def chromium() -> str:
    path = _chromium()
    if path is None:
        if os.environ.get("CI") == "true":
            pytest.fail("Chromium is missing on CI: .ci/run installs Debian's chromium package")
        pytest.skip("Chromium is not installed (Debian: apt-get install chromium); CI installs it and runs this test")
    return path


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):
        pass

    def do_GET(self):
        if self.path == "/favicon.ico":  # the browser asks for it by itself; the site has none
            self.send_response(204)
            self.end_headers()
            return
        super().do_GET()


@pytest.fixture(scope="module")
def server(site):
    """The built site over HTTP on 127.0.0.1 (a free port), for the lifetime of the module."""
    handler = functools.partial(_QuietHandler, directory=str(site))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    httpd.shutdown()
    httpd.server_close()


class Browser:
    """Headless Chromium on a fresh profile, driven through the DevTools protocol on 127.0.0.1."""

    def __init__(self, binary: str):
        self.profile = tempfile.mkdtemp(prefix="forcenet-chromium-")
        self.proc = subprocess.Popen(
            [binary, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-extensions",
             "--disable-default-apps", "--mute-audio", f"--user-data-dir={self.profile}",
             "--remote-debugging-address=127.0.0.1", "--remote-debugging-port=0", "--window-size=1280,1600",
             "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        active = Path(self.profile) / "DevToolsActivePort"
        deadline = time.monotonic() + 60
        while not active.exists() or len(active.read_text().splitlines()) < 2:
            if time.monotonic() > deadline or self.proc.poll() is not None:
                self.close()
                raise RuntimeError("Chromium did not open its DevTools port")
            time.sleep(0.1)
        self.port = int(active.read_text().splitlines()[0])

    def page_socket(self) -> str:
        with urllib.request.urlopen(f"http://127.0.0.1:{self.port}/json/list", timeout=10) as response:
            targets = json.load(response)
        return next(t["webSocketDebuggerUrl"] for t in targets if t["type"] == "page")

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


async def _visit(socket_url: str, url: str, screenshot: Path | None) -> dict:
    """Open ``url``, wait for the load and MathJax, and report requests, console errors, math and images."""
    from tornado.websocket import websocket_connect

    ws = await websocket_connect(socket_url, max_message_size=64 * 2**20)
    ids = iter(range(1, 10**9))
    pending: dict[int, asyncio.Future] = {}
    requests: list[str] = []
    errors: list[str] = []
    loaded = asyncio.get_running_loop().create_future()

    async def reader():
        while True:
            message = await ws.read_message()
            if message is None:
                return
            data = json.loads(message)
            if "id" in data and data["id"] in pending:
                pending.pop(data["id"]).set_result(data)
            method = data.get("method")
            params = data.get("params", {})
            if method == "Network.requestWillBeSent":
                requests.append(params["request"]["url"])
            elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                errors.append("console: " + " ".join(str(a.get("value", a.get("description"))) for a in params["args"]))
            elif method == "Runtime.exceptionThrown":
                errors.append("exception: " + json.dumps(params["exceptionDetails"])[:500])
            elif method == "Log.entryAdded" and params["entry"]["level"] == "error":
                errors.append("log: " + params["entry"]["text"] + " " + params["entry"].get("url", ""))
            elif method == "Page.loadEventFired" and not loaded.done():
                loaded.set_result(True)

    async def call(method: str, **params):
        key = next(ids)
        pending[key] = asyncio.get_running_loop().create_future()
        ws.write_message(json.dumps({"id": key, "method": method, "params": params}))
        reply = await asyncio.wait_for(pending[key], 60)
        assert "error" not in reply, reply
        return reply.get("result", {})

    task = asyncio.ensure_future(reader())
    for domain in ("Page", "Network", "Runtime", "Log"):
        await call(f"{domain}.enable")
    await call("Page.navigate", url=url)
    await asyncio.wait_for(loaded, 60)
    state = await call("Runtime.evaluate", awaitPromise=True, returnByValue=True, expression="""
        (async () => {
          if (window.MathJax && MathJax.startup && MathJax.startup.promise) { await MathJax.startup.promise; }
          await Promise.all([...document.images].map(i => i.complete ? null : new Promise(r => { i.onload = i.onerror = r; })));
          await document.fonts.ready;
          return {
            mathjax: !!(window.MathJax && MathJax.version),
            math_nodes: document.querySelectorAll('.math').length,
            typeset: document.querySelectorAll('mjx-container').length,
            math_errors: document.querySelectorAll('mjx-merror, .MathJax_Error').length,
            images: document.images.length,
            broken: [...document.images].filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src),
            title: document.title,
          };
        })()""")
    if screenshot is not None:
        shot = await call("Page.captureScreenshot", format="png", captureBeyondViewport=False)
        import base64

        screenshot.write_bytes(base64.b64decode(shot["data"]))
    await asyncio.sleep(0.5)  # late console messages and requests
    task.cancel()
    ws.close()
    return {**state["result"]["value"], "requests": requests, "errors": errors}


PAGES = {  # page: (math expected, figures expected)
    "index.html": (True, False),
    "tutorials/exact_tables.html": (True, True),
    "tutorials/symbolic_session.html": (True, True),
    "explanations/order_polytope.html": (True, False),
    "explanations/ensemble.html": (True, True),
    "derivations/scaling_limit.html": (False, True),
    "command_line.html": (False, False),
    "glossary.html": (True, False),
    "api/generated/forcenet.exact.mean_W.html": (False, False),
}


@pytest.mark.slow
@pytest.mark.parametrize("page", sorted(PAGES))
def test_a_page_renders_in_headless_chromium(page, site, server, chromium):
    shots = os.environ.get("FORCENET_DOCS_SCREENSHOTS")
    screenshot = Path(shots) / (page.replace("/", "_") + ".png") if shots else None
    if screenshot is not None:
        screenshot.parent.mkdir(parents=True, exist_ok=True)
    browser = Browser(chromium)
    try:
        state = asyncio.run(_visit(browser.page_socket(), server + page, screenshot))
    finally:
        browser.close()
    math, figures = PAGES[page]
    if math:  # Sphinx loads MathJax on the pages that have math
        assert state["mathjax"], "MathJax did not load"
        assert state["math_nodes"] > 0 and state["typeset"] >= state["math_nodes"], state
        assert any(u.endswith("mathjax/tex-chtml.js") for u in state["requests"])
    assert state["math_errors"] == 0, state
    assert not state["broken"], state["broken"]
    if figures:
        assert state["images"] > 0
    assert not state["errors"], state["errors"]
    foreign = [u for u in state["requests"] if not (u.startswith(server) or u.startswith("data:"))]
    assert not foreign, foreign


# ------------------------------------------------------------------------------------------------ the content


def _pages_and_notes() -> list[Path]:
    return [*USER_PAGES, ROOT / "README.md", *sorted((ROOT / "notes").glob("*.md"))]


def test_no_page_says_the_edge_diverges_as_an_inverse_square_root():
    """The bulk response diverges as (z - |x|)^(-1/3) at the lattice directions (tests/test_edge.py)."""
    wrong = re.compile(r"\(z\s*-\s*\|x\|\)\s*\^\s*[({]?\s*-\s*1\s*/\s*2")
    assert wrong.search("like `(z - |x|)^(-1/2)` there") and wrong.search(r"$(z - |x|)^{-1/2}$")
    found = [f"{p.relative_to(ROOT)}: {m.group(0)}" for p in _pages_and_notes() for m in wrong.finditer(p.read_text())]
    assert not found, found


def test_the_readme_is_a_short_page_that_starts_with_the_two_commands():
    readme = (ROOT / "README.md").read_text().splitlines()
    assert len(readme) <= 80, len(readme)
    assert readme[:5] == ["# forcenet", "", "```bash", "python -m pip install . && forcenet table --N 12",
                          "python -m pip install '.[test]' && python -m pytest"]
    text = "\n".join(readme)
    for page in ("docs/getting_started.md", "docs/command_line.rst", "docs/references.md", "docs/citing.md"):
        assert page.split("/")[-1].rsplit(".", 1)[0] in text and (ROOT / page).is_file(), page
    assert "2026-" not in text  # the history is in the changelog
    links = re.findall(r"\]\(([^)#]+)\)", text)
    assert links and all((ROOT / link).is_file() for link in links), [link for link in links if not (ROOT / link).is_file()]


def test_the_citation_file_is_valid_cff():
    """CITATION.cff by the Citation File Format 1.2.0's required keys and types (the schema was checked with
    jsonschema when it was written), with the package's version and the thesis among its references."""
    import tomllib

    import yaml

    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and isinstance(cff["message"], str) and isinstance(cff["title"], str)
    assert cff["authors"] and all(("name" in a) != ("family-names" in a) for a in cff["authors"])
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert str(cff["version"]) == version and cff["license"] == "MIT" and cff["type"] == "software"
    thesis = [r for r in cff["references"] if r["type"] == "thesis"]
    assert thesis and thesis[0]["authors"][0]["family-names"] == "Ostojic" and thesis[0]["year"] == 2006
    assert "@phdthesis{Ostojic2006" in (DOCS / "citing.md").read_text()


FRONT_DOOR_CALL = re.compile(r"\bforcenet\.(?:table|law|plan|law_plan|sample|sample_plan)\(")


def test_the_tutorials_and_the_how_tos_call_the_front_door():
    tutorials = [p for p in sorted((DOCS / "tutorials").glob("*.md")) if p.name != "index.md"]
    calling = [p.stem for p in tutorials if FRONT_DOOR_CALL.search(p.read_text())]
    assert len(calling) >= 4, calling
    for page in ("getting_started.md", "howto/choosing_a_method.md", "howto/command_line_in_python.md"):
        assert FRONT_DOOR_CALL.search((DOCS / page).read_text()), page


def test_the_command_line_reference_is_the_parser(monkeypatch):
    """Every command and every option the parser knows is on the generated page, and every exit code."""
    import argparse

    pytest.importorskip("docutils", reason="the docs extra (pip install '.[docs]'); .ci/run installs it for this file")
    monkeypatch.syspath_prepend(str(DOCS / "_ext"))  # as docs/conf.py does: the extension imports performance_data

    from forcenet.cli import build_parser
    from forcenet.cli.output import EXIT_CODES

    extension = runpy.run_path(str(DOCS / "_ext" / "cli_reference.py"))
    text = "\n".join(extension["reference_lines"]())
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, command in sub.choices.items():
        assert f"forcenet {name}\n" in text, name
        for action in command._actions:
            for option in action.option_strings:
                assert option in ("-h", "--help") or f"``{option}" in text, (name, option)
    table = (DOCS / "command_line.rst").read_text()
    for code in {int(c) for c in re.findall(r"\b(\d+) ", EXIT_CODES)} | {129, 143}:
        assert f"   * - {code}\n" in table, code


def test_the_command_line_costs_come_from_the_performance_data():
    """The command line page types no cost: its list is rendered from docs/_data/performance.json, the
    performance page's file, and a cost both pages give is one cell of it; every listed command parses."""
    import shlex

    from forcenet.cli import build_parser

    page = (DOCS / "command_line.rst").read_text()
    assert ".. forcenet-command-costs::" in page
    assert not re.search(r"^\s+forcenet \w+ .*#", page, re.M), "a command with a typed cost on the page"
    extension = runpy.run_path(str(DOCS / "_ext" / "performance_data.py"))
    data = json.loads((DOCS / "_data" / "performance.json").read_text())
    lines = extension["command_cost_lines"](data)
    assert len(lines) == len(data["commands"]["rows"]) and not any("{pfaffian." in line for line in lines)
    table_64 = next(r[4] for r in data["pfaffian"]["rows"] if r[0] == 64)
    assert any("--N 64 --force" in line and extension["duration"](table_64) in line for line in lines)
    assert [extension["duration"](s) for s in (0.51, 2.5, 21, 95, 2082, 4300)] == ["0.51 s", "2.5 s", "21 s",
                                                                                   "1.6 min", "35 min", "1.2 h"]
    substitutions = extension["performance_substitutions"](data)
    assert substitutions["pfaffian_table_seconds_64"] == extension["duration"](table_64)
    assert substitutions["dp_memory_28"] == next(r[4] for r in data["dp"]["rows"] if r[0] == 28)
    only = ["forcenet table --N 100 --force"]
    assert len(extension["command_cost_lines"](data, only)) == 1
    with pytest.raises(KeyError, match="lists no command"):
        extension["command_cost_lines"](data, ["forcenet table --N 101"])
    for page in ("howto/large_n.md", "howto/choosing_a_method.md"):  # the costs both pages give, from the data
        text = (DOCS / page).read_text()
        for key in re.findall(r"\{\{ (\w+) \}\}", text):
            assert key in substitutions, (page, key)
        assert "{{ pfaffian_table_seconds_64 }}" in text or (
            "```{forcenet-command-costs}" in text and "forcenet table --N 64 --force --format json\n" in text), page
        assert not re.search(r"^forcenet .*# .*~?\d+(?:\.\d+)? (?:s|min|h)\b", text, re.M), page
    with pytest.raises(KeyError, match="no pfaffian.table_seconds at N = 7"):
        extension["cell"](data, "pfaffian", "table_seconds", 7)
    parser = build_parser()
    for command, _ in data["commands"]["rows"]:
        parser.parse_args(shlex.split(command)[1:])  # argparse exits (code 2) on a command it does not know


def test_api_summaries_survive_abbreviations():
    first_sentence = runpy.run_path(str(DOCS / "conf.py"))["first_sentence"]
    assert first_sentence(["The maps of Sec. 4.6 per bottom row, Eq. (4.88). More."]) == \
        "The maps of Sec. 4.6 per bottom row, Eq. (4.88)."
    assert first_sentence(["One load's law (e.g. W_62). Then more."]) == "One load's law (e.g. W_62)."
    assert first_sentence(["A sum ``W_1 + ... + W_j``. Then more."]) == "A sum ``W_1 + ... + W_j``."


def test_every_derivation_is_on_the_site_without_issue_numbers():
    conf = runpy.run_path(str(DOCS / "conf.py"))
    notes = {p.stem for p in (ROOT / "notes").glob("*.md")} - {"architecture", "architecture_history"}  # the house's map
    pages = {p.stem for p in (DOCS / "derivations").glob("*.md")} - {"index"}
    assert notes == pages, notes ^ pages
    index = (DOCS / "derivations" / "index.md").read_text()
    assert all(f"\n{name}\n" in index for name in pages)
    for name in notes:
        rendered = conf["note_as_page"]((ROOT / "notes" / f"{name}.md").read_text())
        assert not re.search(r"\bissues?\s+\d+", rendered, re.IGNORECASE), name
        assert "](figures/" not in rendered


@pytest.mark.slow
def test_no_api_summary_is_cut_after_an_abbreviation(site):
    cut = []
    for page in [site / "api" / f"{n}.html" for n in ("forcenet", "exact", "numeric", "testing", "errors")]:
        for cell in re.findall(r'<td><p>(.*?)</p></td>', page.read_text(), re.S):
            text = re.sub(r"<[^>]+>", "", cell).strip()
            if re.search(r"\b(?:Eqs?|Secs?|Fig|e\.g|i\.e)\.$", text):
                cut.append(f"{page.name}: {text}")
    assert not cut, cut


@pytest.mark.slow
def test_every_tutorial_is_a_downloadable_executed_notebook(site):
    for name in TUTORIALS:
        html = (site / "tutorials" / f"{name}.html").read_text()
        assert f'href="../notebooks/{name}.ipynb"' in html, name
        notebook = json.loads((site / "notebooks" / f"{name}.ipynb").read_text())
        code = [c for c in notebook["cells"] if c["cell_type"] == "code"]
        assert code and any(c.get("outputs") for c in code), name


@pytest.mark.slow
def test_the_performance_page_plots_its_scaling_from_its_data(site):
    html = (site / "performance.html").read_text()
    assert re.search(r'<img[^>]+src="_images/[^"]+\.png"', html) and "one prime scales as N^" in html
    data = json.loads((DOCS / "_data" / "performance.json").read_text())
    for N, *_ in data["pfaffian"]["rows"]:
        assert f"<td><p>{N}</p></td>" in html, N
