"""Checks of a report.html as a person reads it (issue 33), shared by report_pages_test.py.

Structure (html.parser): element ids unique; the answer (an element of class "answer") before
the first section heading; every in-page link lands on an element; every figure an inline SVG with a title or axis label in words, and
no "[1]" for a unit; no number with more than 7 significant digits in the prose and tables
(integers, figures, code, preformatted notes and provenance left out).
Rendering (headless Chromium, Debian's chromium): the page loads without a script or resource
error and every figure has a non-zero size.
"""
import html.parser
import json
import os
import re
import subprocess
import tempfile

MAX_DIGITS = 7
NUMBER = re.compile(r"(?<![\w.])[-+]?(\d+\.\d+|\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def significant_digits(token):
    mantissa = re.split(r"[eE]", token.lstrip("+-"))[0]
    digits = mantissa.replace(".", "").lstrip("0")
    if "." not in mantissa:
        digits = digits.rstrip("0") or "0"  # 12000 has 2
    return len(digits)


class _Page(html.parser.HTMLParser):
    SKIP = {"svg", "pre", "code", "style", "script"}

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids, self.anchors, self.stack, self.skip_depth = [], [], [], 0
        self.first_h2_at = None
        self.answer_at = None
        self.position = 0
        self.text = []  # (text, in provenance)
        self.figures = []  # per <svg>: list of its texts
        self.in_provenance = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.position += 1
        if "id" in a:
            self.ids.append(a["id"])
        if tag == "a" and (a.get("href") or "").startswith("#"):
            self.anchors.append(a["href"][1:])
        if "answer" in (a.get("class") or "").split() and self.answer_at is None:
            self.answer_at = self.position
        if tag == "h2":
            if self.first_h2_at is None:
                self.first_h2_at = self.position
            self.in_provenance = False
        if tag == "svg" and self.skip_depth == 0:
            self.figures.append([])
        if tag in self.SKIP:
            self.skip_depth += 1
        self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag in self.SKIP and self.skip_depth > 0:
            self.skip_depth -= 1
        if self.stack and self.stack[-1] == tag:
            self.stack.pop()

    def handle_data(self, data):
        if self.stack and self.stack[-1] == "h2" and "Provenance" in data:
            self.in_provenance = True
        if self.skip_depth > 0:
            if self.figures and self.stack and self.stack[-1] == "text" or (self.stack and self.stack[-1] == "tspan"):
                if self.figures:
                    self.figures[-1].append(data.strip())
            return
        self.text.append((data, self.in_provenance))


def structure_problems(html_text):
    """The problems of a report's HTML, as sentences (empty: none)."""
    p = _Page()
    p.feed(html_text)
    problems = []
    seen = set()
    for i in p.ids:
        if i in seen:
            problems.append(f"element id '{i}' used more than once")
        seen.add(i)
    for a in p.anchors:
        if a not in seen:
            problems.append(f"link to #{a}, which no element is")
    if "gnuplot_svg." in html_text:
        problems.append("a figure calls gnuplot's JavaScript (gnuplot_svg.*), which the page does not hold: "
                        "hover texts must be the SVG's own <title> tooltips")
    if p.answer_at is None:
        problems.append("no answer (an element of class 'answer')")
    elif p.first_h2_at is not None and p.answer_at > p.first_h2_at:
        problems.append("the answer comes after the first section heading")
    for k, texts in enumerate(p.figures):
        labels = [t for t in texts if re.search(r"[A-Za-z]{3}", t)]
        if not labels:
            problems.append(f"figure {k + 1} has no title or axis label")
        for t in labels:
            if re.search(r"\[1\]", t):
                problems.append(f"figure {k + 1}: '{t}' gives 1 as a unit (say dimensionless, or leave it out)")
    for data, provenance in p.text:
        if provenance:
            continue
        for m in NUMBER.finditer(data):
            if re.fullmatch(r"[-+]?\d+", m.group(0)):
                continue  # a count, an index or a seed
            if significant_digits(m.group(0)) > MAX_DIGITS:
                context = data[max(0, m.start() - 40):m.end() + 20].strip()
                problems.append(f"number {m.group(0)} has more than {MAX_DIGITS} significant digits: ...{context}...")
    return problems


PROBE = """<script>(function(){var errors=[];
window.addEventListener('error',function(e){errors.push(String(e.message||(e.target&&(e.target.src||e.target.href))||'error'));},true);
var ce=console.error;console.error=function(){errors.push(Array.prototype.join.call(arguments,' '));ce.apply(console,arguments);};
window.addEventListener('load',function(){var sizes=[];document.querySelectorAll('svg').forEach(function(s){
if(s.parentElement&&s.parentElement.closest('svg'))return;var r=s.getBoundingClientRect();sizes.push([r.width,r.height]);});
var p=document.createElement('pre');p.id='poise-render-check';p.textContent=JSON.stringify({errors:errors,figures:sizes});
document.body.appendChild(p);});})();</script>"""


def chromium():
    for exe in ("chromium", "chromium-browser"):
        for d in os.environ.get("PATH", "").split(os.pathsep):
            if os.access(os.path.join(d, exe), os.X_OK):
                return os.path.join(d, exe)
    return None


def render_problems(report_path, exe):
    """Loads the page in headless Chromium with a probe; the problems seen (empty: none)."""
    with open(report_path, encoding="utf-8") as f:
        text = f.read()
    at = text.find("<head>")
    probed = text[:at + 6] + PROBE + text[at + 6:] if at >= 0 else PROBE + text
    folder = os.path.dirname(os.path.abspath(report_path))
    with tempfile.NamedTemporaryFile("w", suffix=".html", dir=folder, delete=False, encoding="utf-8") as f:
        f.write(probed)
        probe_path = f.name
    try:
        with tempfile.TemporaryDirectory() as profile:
            out = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + profile,
                                  "--window-size=1100,900", "--virtual-time-budget=5000", "--dump-dom",
                                  "file://" + probe_path], capture_output=True, text=True, timeout=600).stdout
    finally:
        os.unlink(probe_path)
    m = re.search(r'<pre id="poise-render-check">(.*?)</pre>', out, re.S)
    if not m:
        return ["the page did not finish loading in Chromium (no probe result)"]
    result = json.loads(html.unescape(m.group(1)))
    problems = [f"error while loading: {e}" for e in result["errors"]]
    for k, (w, h) in enumerate(result["figures"]):
        if not (w > 0 and h > 0):
            problems.append(f"figure {k + 1} is drawn with size {w} x {h}")
    return problems
