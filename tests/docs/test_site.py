"""The built guide as a person reads it (issue 55): every page of build/docs/site opened in
headless Chromium (Debian's `chromium`) from a local server: no script or resource error, no
image that does not load, a title and a heading; every internal link and anchor resolves in
the rendered pages; nothing is loaded from another site (the guide works offline); the search
finds pages offline; the gallery shows a report of every study kind.

The site is built by scripts/docs.sh (the test command runs it before ctest). Run by ctest
(guide_site) with POISE_EXE and POISE_SOURCE_DIR set."""
import functools
import glob
import html
import html.parser
import http.server
import json
import os
import re
import shutil
import subprocess
import tempfile
import threading
import urllib.parse
from concurrent.futures import ThreadPoolExecutor

import pytest

SRC = os.environ.get("POISE_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
EXE = os.environ.get("POISE_EXE", os.path.join(SRC, "build", "poise"))
SITE = os.path.join(os.path.dirname(os.path.abspath(EXE)), "docs", "site")

PROBE = """<script>(function(){var errors=[];
window.addEventListener('error',function(e){var t=e.target;
errors.push(t&&t!==window?('could not load '+(t.src||t.href)):('script error: '+e.message));},true);
window.addEventListener('load',function(){var broken=[];document.querySelectorAll('img').forEach(function(i){
if(!(i.complete&&i.naturalWidth>0))broken.push(i.getAttribute('src'));});
var p=document.createElement('pre');p.id='poise-guide-check';
p.textContent=JSON.stringify({errors:errors,broken_images:broken,title:document.title});
document.body.appendChild(p);});})();</script>"""


class Page(html.parser.HTMLParser):
    """What a rendered page holds: its ids, its links, its first-level headings, what it loads."""

    def __init__(self):
        super().__init__()
        self.ids, self.links, self.loads, self.h1 = set(), [], [], 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        if tag == "a" and a.get("href") is not None:
            self.links.append(a["href"])
        if tag in ("script", "img", "iframe") and a.get("src"):
            self.loads.append(a["src"])
        if tag == "link" and a.get("href") and "stylesheet" in (a.get("rel") or ""):
            self.loads.append(a["href"])
        if tag == "h1":
            self.h1 += 1


def chromium():
    for exe in ("chromium", "chromium-browser"):
        if shutil.which(exe):
            return shutil.which(exe)
    pytest.fail("chromium is not installed: scripts/install_deps.sh --tests installs it")


def dump(exe, url):
    with tempfile.TemporaryDirectory() as profile:
        return subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + profile,
                               "--window-size=1200,900", "--virtual-time-budget=5000", "--dump-dom", url],
                              capture_output=True, text=True, timeout=600).stdout


@pytest.fixture(scope="module")
def served():
    """A copy of the site, every guide page with the probe, served on 127.0.0.1; yields (root,
    base url, {page: rendered DOM})."""
    if not os.path.isfile(os.path.join(SITE, "index.html")):
        pytest.fail(f"{SITE} is not built: scripts/docs.sh builds it (the test command runs it)")
    exe = chromium()
    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "site")
        shutil.copytree(SITE, root)
        pages = guide_pages(root)
        for page in pages:
            path = os.path.join(root, page)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            with open(path, "w", encoding="utf-8") as f:
                f.write(text.replace("<head>", "<head>" + PROBE, 1))
        handler = functools.partial(Quiet, directory=root)
        server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        base = f"http://127.0.0.1:{server.server_address[1]}/"
        try:
            with ThreadPoolExecutor(max_workers=2) as pool:
                doms = dict(zip(pages, pool.map(lambda p: dump(exe, base + p), pages)))
            yield root, base, doms
        finally:
            server.shutdown()


class Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def guide_pages(root):
    """The guide's own pages (the gallery's reports are checked by tests/reports)."""
    pages = [os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "**", "*.html"), recursive=True)]
    return sorted(p for p in pages if not p.startswith("gallery" + os.sep) and p != "404.html")


def probe_result(dom):
    m = re.search(r'<pre id="poise-guide-check">(.*?)</pre>', dom, re.S)
    return json.loads(html.unescape(m.group(1))) if m else None


def parsed(dom):
    p = Page()
    p.feed(dom)
    return p


def test_every_page_loads_with_a_title_and_nothing_broken(served):
    _, _, doms = served
    assert len(doms) >= 20, f"only {len(doms)} pages in the guide"
    problems = []
    for page, dom in doms.items():
        result = probe_result(dom)
        if result is None:
            problems.append(f"{page}: did not finish loading in Chromium")
            continue
        problems += [f"{page}: {e}" for e in result["errors"]]
        problems += [f"{page}: image {src} does not load" for src in result["broken_images"]]
        if not result["title"].strip() or result["title"].strip() == "Poise":
            if page != "index.html":
                problems.append(f"{page}: no title of its own ({result['title']!r})")
        if parsed(dom).h1 < 1:
            problems.append(f"{page}: no heading")
    assert not problems, "\n".join(problems)


def test_every_internal_link_and_anchor_resolves(served):
    root, _, doms = served
    ids = {page: parsed(dom).ids for page, dom in doms.items()}
    problems, checked = [], 0
    for page, dom in doms.items():
        for href in parsed(dom).links:
            url = urllib.parse.urlparse(href)
            if url.scheme in ("http", "https", "mailto") or href.startswith("//"):
                continue
            target = os.path.normpath(os.path.join(os.path.dirname(page), urllib.parse.unquote(url.path))) if url.path else page
            checked += 1
            if not os.path.isfile(os.path.join(root, target)):
                problems.append(f"{page}: link {href}: no page {target}")
            elif url.fragment and target in ids and url.fragment not in ids[target]:
                problems.append(f"{page}: link {href}: {target} has no anchor #{url.fragment}")
    assert checked > 100, f"only {checked} internal links checked"
    assert not problems, "\n".join(problems)


def test_nothing_is_loaded_from_another_site(served):
    _, _, doms = served
    remote = [f"{page}: {src}" for page, dom in doms.items() for src in parsed(dom).loads
              if re.match(r"(https?:)?//", src)]
    assert not remote, "the guide must work offline:\n" + "\n".join(remote)


def search_results(root, base, query):
    """The search's results for query, in Chromium, the index searched in the page itself (a web
    worker's answer would arrive after --dump-dom; the search code and index are the same)."""
    with open(os.path.join(root, "index.html"), encoding="utf-8") as f:
        text = f.read()
    with open(os.path.join(root, "search-probe.html"), "w", encoding="utf-8") as f:
        f.write(text.replace("<head>", "<head><script>window.Worker = undefined;</script>", 1))
    dom = dump(chromium(), base + "search-probe.html?q=" + urllib.parse.quote(query))
    m = re.search(r'<div id="mkdocs-search-results"[^>]*>(.*?)</div>', dom, re.S)
    return re.findall(r'<a href="([^"]+)"', m.group(1)) if m else None


def test_search_works_offline(served):
    root, base, _ = served
    found = search_results(root, base, "cogging")
    assert found is not None, "no search results element on the page"
    assert any("metrologist.html" in href for href in found), f"'cogging' does not find the metrologist's page: {found}"
    assert search_results(root, base, "zyxwvutsrq") == [], "a word in no page finds something"


def test_the_gallery_shows_a_report_of_every_study_kind(served):
    _, _, doms = served
    kinds = re.findall(r"^  ([a-z0-9_]+)$", subprocess.run([EXE, "keys"], capture_output=True, text=True).stdout, re.M)
    assert kinds, "poise keys lists no kind"
    gallery = parsed(doms["gallery.html"])
    missing = [k for k in kinds if k not in gallery.ids]
    assert not missing, f"the gallery has no report of: {', '.join(missing)}"
    pictures = [s for s in gallery.loads if s.startswith("gallery/") and s.endswith(".png")]
    assert len(pictures) >= len(kinds)
    for picture in pictures:
        assert os.path.getsize(os.path.join(SITE, picture)) > 10000, f"{picture} is too small to show a report"
