"""The HTML book opened in a real browser (headless Chromium driven by Selenium).

The site is built from the committed, executed notebooks (nothing is executed) into a temporary
folder, served on 127.0.0.1 (the search page needs http), and every page is opened. On each page:
MathJax finished, left no raw TeX and no error; every image loaded; every sidebar and
previous/next link leads to a page of the book; cells tagged ``hide-input``/``hide-cell`` are
collapsed; every solution (cells tagged ``solution``, folded whole when the site is staged) shows
nothing but its headings before a click and opens on one, on every chapter page; each chapter's
download button leads to its notebook; the browser console has no
error; nothing is loaded from outside the book; the text shows no machine path and no words about
how the book was made. The search page finds a word of each chapter's title on that chapter's
page.

A machine without Chromium, its driver or Selenium skips these tests with the command that
installs them; under CI (``CI=true``) a missing browser is a failure instead.
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import threading
import time
from pathlib import Path
from urllib.parse import quote, urlsplit

import pytest

from amdo_lab.course.book import build_site
from amdo_lab.chapters import available_chapters
from amdo_lab.course.environment import BROWSER_INSTALL_COMMAND, find_browser

INSTALL_HINT = (
    f"install Chromium and its driver ({BROWSER_INSTALL_COMMAND}) and Selenium "
    "(pip install -r environment.txt)"
)
CHROMIUM_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
    "--no-first-run", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--window-size=1280,900",
)
PAGE_TIMEOUT_S = 60
# Same patterns as ../shared/tools/check_notebooks.py (LEAK and PROCESS): the book speaks about
# the methods, never about the machine it was built on or how it was made.
MACHINE_PATH = re.compile(r"(/root/|/home/|/tmp/|/work/|/Users/|[A-Z]:\\Users\\)")
PROCESS_WORDS = re.compile(
    r"\b(the issue|this issue|issue's|target missed|(?:our|the) (?:speed |accuracy )?target"
    r"(?! (?:image|shape|point|set|frame|pose|cloud|distribution|sequence|domain))|"
    r"previous version|earlier version|previous default|for honesty|done[- ]when)\b",
    re.IGNORECASE,
)
# TeX that MathJax did not typeset. Inline $...$ follows the usual rule (no space inside the
# dollars, no digit after the closing one), so a price such as "$5 and $10" is not TeX.
RAW_TEX = re.compile(r"(\$[^\s$][^$\n]*?(?<=\S)\$(?!\d)|\\begin\{|\\\(|\\\[|\\frac\b|\\mathbf\b)")


def _missing_browser() -> str | None:
    """Why the browser test cannot run here, or None when it can."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "Selenium is not installed: " + INSTALL_HINT
    browser = find_browser()
    if browser.binary is None:
        return "Chromium is not installed: " + INSTALL_HINT
    if browser.driver is None:
        return "chromedriver is not installed: " + INSTALL_HINT
    return None


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The book built from the committed notebooks, served over http on 127.0.0.1."""
    reason = _missing_browser()
    if reason is not None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"CI must run the browser test, but {reason}")
        pytest.skip(reason)
    build_dir = tmp_path_factory.mktemp("book-build")
    index = build_site(build_dir, warnings_as_errors=True)  # a broken reference fails here
    site_dir = index.parent
    handler = functools.partial(_QuietHandler, directory=str(site_dir))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield site_dir, f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 (signature of the base class)
        pass


@pytest.fixture(scope="module")
def browser(site, tmp_path_factory):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    found = find_browser()
    options = webdriver.ChromeOptions()
    options.binary_location = found.binary
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # An explicit driver path: Selenium Manager is never asked to download a driver.
    service = Service(executable_path=found.driver)
    driver = webdriver.Chrome(options=options, service=service)
    driver.set_page_load_timeout(PAGE_TIMEOUT_S)
    driver.set_script_timeout(PAGE_TIMEOUT_S)
    try:
        yield driver
    finally:
        driver.quit()


# Runs in the page once it has loaded: waits for MathJax and the images, then reports.
_INSPECT_PAGE = r"""
const done = arguments[arguments.length - 1];
(async () => {
  const math = document.querySelectorAll('.math, div.math, span.math').length;
  let mathjax = 'absent';
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
    mathjax = 'finished';
  } else if (window.MathJax) {
    mathjax = 'not started';
  }
  // MathJax's own record of each formula: its TeX source and the tree it built. An error box
  // (merror) is a TeX syntax error; a red mtext is an undefined macro (the noundefined package).
  function mathProblems(kind) {
    if (mathjax !== 'finished') return [];
    const found = [];
    for (const item of MathJax.startup.document.math) {
      let bad = false;
      item.root.walkTree(node => {
        if (kind === 'error' && node.isKind('merror')) bad = true;
        if (kind === 'undefined' && node.isKind('mtext') &&
            node.attributes.get('mathcolor') === 'red') bad = true;
      });
      if (bad) found.push(String(item.math).slice(0, 80));
    }
    return found.slice(0, 5);
  }
  const images = Array.from(document.images);
  images.forEach(img => { img.loading = 'eager'; });
  await Promise.all(images.map(img => img.complete ? null :
      new Promise(resolve => { img.onload = img.onerror = resolve; })));
  const article = document.querySelector('article') || document.body;
  const prose = article.cloneNode(true);
  prose.querySelectorAll('pre, code, script, style, mjx-container, .highlight')
       .forEach(node => node.remove());
  const absolute = (url) => new URL(url, document.baseURI).href;
  done({
    math: math,
    mathjax: mathjax,
    typeset: document.querySelectorAll('mjx-container').length,
    mathErrors: mathProblems('error'),
    errorBoxes: document.querySelectorAll('mjx-merror').length,
    undefinedMacros: mathProblems('undefined'),
    prose: prose.textContent,
    text: document.body.textContent,
    brokenImages: images.filter(img => !(img.complete && img.naturalWidth > 0))
        .map(img => img.getAttribute('src')),
    nImages: images.length,
    sidebar: Array.from(document.querySelectorAll('nav.bd-docs-nav a')).map(a => a.href),
    prevNext: Array.from(document.querySelectorAll('.prev-next-area a')).map(a => a.href),
    downloads: Array.from(document.querySelectorAll('a[href*="_sources/"]')).map(a => a.href),
    resources: performance.getEntriesByType('resource').map(entry => entry.name),
    domResources: Array.from(document.querySelectorAll(
        'script[src], link[rel="stylesheet"][href], link[rel="preload"][href], img[src], ' +
        'link[rel="icon"][href], source[src], iframe[src]'))
        .map(node => absolute(node.getAttribute('src') || node.getAttribute('href'))),
    openHidden: Array.from(document.querySelectorAll('details.hide, details.toggle-details'))
        .filter(node => node.open).length,
    hidden: document.querySelectorAll('details.hide').length,
  });
})().catch(error => done({fatal: String(error)}));
"""


def _pages(site_dir: Path) -> list[str]:
    return sorted(path.name for path in site_dir.glob("*.html"))


def _console_errors(driver) -> list[str]:
    return [entry["message"] for entry in driver.get_log("browser") if entry["level"] == "SEVERE"]


def _inspect(driver, url: str) -> dict:
    driver.get(url)
    report = driver.execute_async_script(_INSPECT_PAGE)
    assert "fatal" not in report, f"{url}: the page script failed: {report.get('fatal')}"
    report["console"] = _console_errors(driver)
    return report


@pytest.fixture(scope="module")
def reports(site, browser):
    """What the browser saw on every page of the book, opened once: {page name: report}."""
    site_dir, base = site
    pages = _pages(site_dir)
    chapters = [chapter.slug + ".html" for chapter in available_chapters()]
    assert set(chapters) <= set(pages), f"chapters without a page: {set(chapters) - set(pages)}"
    return {page: _inspect(browser, base + page) for page in pages}


def _chapter_pages() -> list[str]:
    return [chapter.slug + ".html" for chapter in available_chapters()]


def _assert_none(problems: list[str]) -> None:
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(problems)


def test_equations_are_typeset_with_no_raw_tex_and_no_error(reports):
    problems = []
    for page, report in reports.items():
        if report["math"] and report["mathjax"] != "finished":
            problems.append(f"{page}: {report['math']} equations but MathJax is {report['mathjax']}")
        elif report["math"] and not report["typeset"]:
            problems.append(f"{page}: equations were not typeset")
        if report["mathErrors"] or report["errorBoxes"]:
            problems.append(f"{page}: {report['errorBoxes']} MathJax error(s): {report['mathErrors']}")
        if report["undefinedMacros"]:
            problems.append(f"{page}: undefined TeX macros: {report['undefinedMacros']}")
        for raw in list(RAW_TEX.finditer(report["prose"]))[:3]:
            context = report["prose"][max(0, raw.start() - 60): raw.end() + 60].replace("\n", " ")
            problems.append(f"{page}: raw TeX {raw.group(0)!r} in ...{context}...")
    _assert_none(problems)


def test_every_image_loads(reports):
    _assert_none([
        f"{page}: {len(report['brokenImages'])} of {report['nImages']} images did not load: "
        f"{report['brokenImages'][:3]}"
        for page, report in reports.items() if report["brokenImages"]
    ])


def test_sidebar_previous_next_and_download_links_lead_into_the_book(site, reports):
    site_dir, base = site
    pages, chapters = set(reports), _chapter_pages()
    problems = []
    for page, report in reports.items():
        for link in report["sidebar"] + report["prevNext"]:
            if not link.startswith(base) or urlsplit(link).path.lstrip("/") not in pages:
                problems.append(f"{page}: link {link} does not lead to a page of the book")
        if page in chapters or page == "index.html":
            listed = {urlsplit(link).path.lstrip("/") for link in report["sidebar"]}
            missing = set(chapters) - listed - {page}
            if missing:
                problems.append(f"{page}: the sidebar misses {sorted(missing)}")
            if not report["prevNext"]:
                problems.append(f"{page}: no previous/next link")
        if page in chapters:
            notebook = page.replace(".html", ".ipynb")
            targets = [urlsplit(link).path.lstrip("/") for link in report["downloads"]]
            if f"_sources/{notebook}" not in targets or not (site_dir / "_sources" / notebook).exists():
                problems.append(f"{page}: no working download link for {notebook} (found {targets})")
    _assert_none(problems)


def test_nothing_is_loaded_from_outside_the_book_and_the_console_is_clean(site, reports):
    _, base = site
    problems = []
    for page, report in reports.items():
        outside = sorted({url for url in report["resources"] + report["domResources"]
                          if not url.startswith(base) and not url.startswith("data:")})
        if outside:
            problems.append(f"{page}: loads {len(outside)} resource(s) from outside the book: "
                            f"{outside[:3]}")
        if report["console"]:
            problems.append(f"{page}: console errors: {report['console'][:3]}")
    _assert_none(problems)


def test_hidden_cells_are_folded(reports):
    _assert_none([f"{page}: {report['openHidden']} hidden cell(s) are open on load"
                  for page, report in reports.items() if report["openHidden"]])
    # chapter 0's warm-up solution is the example every chapter follows
    assert reports["00_introduction.html"]["hidden"] >= 1, "chapter 0's solution is not folded"


# Runs in a chapter page: every folded solution part (a dropdown admonition of solution prose, a
# code cell folded with its output), its visible text before a click, and after one.
_PROBE_SOLUTIONS = r"""
const done = arguments[arguments.length - 1];
(async () => {
  const sleep = ms => new Promise(resolve => setTimeout(resolve, ms));
  const article = document.querySelector('article') || document.body;
  const heading = Array.from(article.querySelectorAll('h1, h2'))
      .some(h => /^\s*Solutions\b/.test(h.textContent));
  const parts = item => {
    if (item.classList.contains('admonition')) {
      const title = item.querySelector(':scope > .admonition-title');
      return {kind: 'prose', toggle: title, body: Array.from(item.children).filter(c => c !== title)};
    }
    const details = item.querySelector(':scope > details');
    if (!details) return {kind: 'code', toggle: null, body: Array.from(item.children)};
    // the folded input, and the output too: with hide-input alone the output would sit outside
    return {kind: 'code', toggle: details.querySelector(':scope > summary'),
            body: Array.from(details.children).filter(c => c.tagName !== 'SUMMARY')
                .concat(Array.from(item.children).filter(c => c !== details))};
  };
  const visible = nodes => nodes
      .filter(n => n.checkVisibility({checkOpacity: true, checkVisibilityCSS: true}) &&
                   n.getBoundingClientRect().height > 0)
      .map(n => n.innerText.trim()).join(' ').replace(/\s+/g, ' ').trim();
  const found = [];
  for (const item of article.querySelectorAll('.admonition.amdo-solution, .tag_amdo-solution')) {
    const {kind, toggle, body} = parts(item);
    const text = body.map(n => n.textContent).join(' ').replace(/\s+/g, ' ').trim().slice(0, 60);
    const before = visible(body);
    const pageBefore = article.innerText.replace(/\s+/g, ' ');
    let after = '';
    if (toggle) {
      toggle.click();
      await sleep(500);
      after = visible(body);
      toggle.click();
      await sleep(100);
    }
    found.push({kind, text, before, after, toggle: !!toggle,
                inPage: text.length > 20 && pageBefore.includes(text.slice(0, 40))});
  }
  done({heading, found});
})().catch(error => done({fatal: String(error)}));
"""


def test_every_solution_is_folded_whole_and_opens_on_a_click(site, browser):
    _, base = site
    problems = []
    for page in _chapter_pages():
        browser.get(base + page)
        probe = browser.execute_async_script(_PROBE_SOLUTIONS)
        assert "fatal" not in probe, f"{page}: the probe failed: {probe.get('fatal')}"
        if probe["heading"] and not probe["found"]:
            problems.append(f"{page}: a Solutions section but no folded solution (cells tagged 'solution')")
        for part in probe["found"]:
            where = f"{page}: solution {part['kind']} {part['text'][:40]!r}"
            if part["before"] or part["inPage"]:
                problems.append(f"{where} is visible before a click: {part['before'][:60]!r}")
            if not part["toggle"]:
                problems.append(f"{where} has nothing to click")
            elif not part["after"]:
                problems.append(f"{where} does not open on a click")
    _assert_none(problems)


def test_no_page_shows_a_machine_path_or_how_the_book_was_made(reports):
    problems = []
    for page, report in reports.items():
        leak = MACHINE_PATH.search(report["text"])
        if leak:
            context = report["text"][max(0, leak.start() - 40): leak.end() + 40]
            problems.append(f"{page}: shows a machine path: {context!r}")
        words = sorted({match.group(0) for match in PROCESS_WORDS.finditer(report["text"])})
        if words:
            problems.append(f"{page}: speaks about how the book was made: {words}")
    _assert_none(problems)


def _search_word(title: str) -> str:
    """The longest word of a chapter title: specific enough to find that chapter."""
    return max(re.findall(r"[A-Za-z]+", title), key=len).lower()


def test_search_finds_a_word_of_each_chapter(site, browser):
    _, base = site
    problems = []
    for chapter in available_chapters():
        word = _search_word(chapter.title)
        browser.get(f"{base}search.html?q={quote(word)}")
        found = _wait_for_search(browser)
        if f"{chapter.slug}.html" not in {urlsplit(link).path.lstrip("/") for link in found}:
            problems.append(f"searching {word!r} does not list {chapter.slug}.html (found {found})")
        errors = _console_errors(browser)
        if errors:
            problems.append(f"search for {word!r}: console errors {errors[:3]}")
    assert not problems, "\n".join(problems)


def _wait_for_search(driver, timeout_s: float = PAGE_TIMEOUT_S) -> list[str]:
    """Links listed once the search page says it finished (Sphinx fills #search-results)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        state = driver.execute_script(
            "const box = document.getElementById('search-results');"
            "if (!box) return null;"
            "const summary = box.querySelector('.search-summary, p');"
            "return {summary: summary ? summary.textContent : '',"
            "        links: Array.from(box.querySelectorAll('ul a')).map(a => a.href)};"
        )
        if state and state["summary"].strip() and "Searching" not in state["summary"]:
            return state["links"]
        time.sleep(0.2)
    raise AssertionError("the search page did not finish within the time limit")


# TeX source left as text: a display delimiter, or a TeX control word (\tfrac, \Big, \begin, \sum, ...).
# The rendered prose keeps neither once MathJax has typeset a formula; either one left means the
# markdown never handed the formula to MathJax (a display broken by a line that starts with "+" or
# "-", which Markdown reads as a list item, or $$ inside a paragraph).
TEX_SOURCE = re.compile(r"\$\$|\\[A-Za-z]{2,}")


def test_chapter_prose_shows_no_tex_source(reports):
    """No chapter page shows "$$" or a TeX control word in its prose, outside MathJax's output."""
    problems = []
    for page in _chapter_pages():
        prose = reports[page]["prose"]
        for raw in list(TEX_SOURCE.finditer(prose))[:3]:
            context = prose[max(0, raw.start() - 60): raw.end() + 60].replace("\n", " ")
            problems.append(f"{page}: TeX source {raw.group(0)!r} in ...{context}...")
    _assert_none(problems)
