"""Open three HTML reports in headless Chromium: no console error, nothing fetched outside.

For .ci/run (its own phase; Debian 12 package names):

    # --- report: report.html renders in a real browser, offline ------------------------
    # apt-get install -y chromium-headless-shell     # or: chromium
    # PYTHONPATH=src python scripts/check_report.py --out ci-report-check --demo
    # (exit 0: every report loaded with no console error, no exception, no request
    #  outside its file; screenshots ci-report-check/*.png show the verdict and the
    #  first figure)

Three reports are made from small synthetic data (fast fits): a multi-mode fit
(uniaxial at two rates, equibiaxial, planar), a ramp–hold fit (a relaxation history),
and a DMA fit (frequency sweeps at four temperatures with a WLF shift, and two ramps).
Each is checked twice:

* statically: every ``src``/``href``/``url(...)`` of the file is a ``data:`` URI or a
  ``#fragment``, and the file has no ``<script>``;
* in the browser, through the Chrome DevTools protocol over ``--remote-debugging-pipe``
  (standard library only): the page loads, no ``Runtime.consoleAPICalled`` of type
  error, no ``Runtime.exceptionThrown``, no ``Log.entryAdded`` at level error, every
  ``Network.requestWillBeSent`` is the file itself or a ``data:`` URI; the page fits
  a 1280 px window with no horizontal scrollbar (the document no wider than the
  viewport; else the widest element is named); then a 1280 x 900 screenshot
  (``Page.captureScreenshot``).

Usage: ``python scripts/check_report.py [--out DIR] [--browser PATH] [--demo]``; exit 1
with the problems listed when a check fails, 2 when no browser is found. ``--demo`` also
runs ``vhfit demo`` (about a minute) and checks its report the same way, under 3 MB,
printing how long it took to write.
"""

from __future__ import annotations

import argparse
import base64
import contextlib
import fcntl
import io
import json
import os
import re
import select
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from html.parser import HTMLParser
from pathlib import Path

import numpy as np

import vhfit
from vhfit import tts

BROWSERS = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome",
            "/usr/lib/chromium/chromium-headless-shell", "/usr/lib/chromium/chromium")
P = dict(C10=0.2, C01=0.05, G1=1.5, tau1=0.05)
#: the browser window's width (px): a report must fit it without a horizontal scrollbar
WIDTH = 1280
#: JavaScript: "" when the page is no wider than its window, else its width and the
#: first element whose right edge lies beyond the window
WIDEST = """(() => {
  const d = document.documentElement, w = d.clientWidth;
  if (d.scrollWidth <= w) return "";
  for (const e of document.body.querySelectorAll("*")) {
    const r = e.getBoundingClientRect();
    if (r.right > w + 0.5)
      return `${d.scrollWidth} px; <${e.tagName.toLowerCase()}` +
        `${e.id ? " id=" + e.id : ""}> ends at ${Math.round(r.right)} px`;
  }
  return `${d.scrollWidth} px`;
})()"""


# ------------------------------------------------------------------ the three fits
def _fit(items, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(items, hyperelastic="mooney_rivlin", n_prony=1, seed=0,
                               maxiter=40, **kw)


def multi_mode():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(0.0, -0.4, 21)
    out = [vhfit.Curve(strain=eps, stress=m.stress(P, strain=eps, strain_rate=r,
                                                   measure="engineering"),
                       strain_rate=r, name=f"uniaxial {r:g}/s") for r in (-0.1, -10.0)]
    ten = np.linspace(0.0, 0.5, 21)
    for mode in ("equibiaxial", "planar"):
        s = m.stress(P, strain=ten, strain_rate=1.0, measure="engineering", deformation=mode)
        out.append(vhfit.Curve(strain=ten, stress=s, strain_rate=1.0, deformation=mode,
                               name=f"{mode} <1/s>"))
    return _fit(out), out


def ramp_hold():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    t = np.concatenate([np.linspace(0.0, 1.0, 21), np.linspace(1.05, 30.0, 40)])
    eps = np.where(t <= 1.0, -0.3 * t, -0.3)
    curves = []
    for scale, name in ((1.0, "ramp-hold 0.3/s"), (10.0, "ramp-hold 3/s")):
        s = m.stress(P, strain=eps, time=t / scale, measure="engineering")
        curves.append(vhfit.Curve(strain=eps, stress=s, time=t / scale, name=name))
    return _fit(curves), curves


def dma():
    c1, c2, t_ref = 8.86, 101.6, 20.0
    law = tts.WLF(c1, c2, t_ref)
    e_inf = 6.0 * (P["C10"] + P["C01"])
    f = np.logspace(-1, 2, 21)
    items = []
    for T in (0.0, 20.0, 40.0, 60.0):
        wt = 2 * np.pi * f * 10 ** float(law.log_aT(T)) * P["tau1"]
        e1 = e_inf + P["G1"] * wt**2 / (1 + wt**2)
        e2 = P["G1"] * wt / (1 + wt**2)
        items.append(vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2, temperature=T,
                                          name=f"dma {T:g} C"))
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(0.0, -0.4, 21)
    for r in (-1.0, -100.0):
        items.append(vhfit.Curve(strain=eps, stress=m.stress(P, strain=eps, strain_rate=r,
                                                             measure="engineering"),
                                 strain_rate=r, name=f"rate {r:g}/s",
                                 metadata={"temperature": t_ref}))
    return _fit(items, shift_factors=law), items


# ------------------------------------------------------------------ static check
class _Refs(HTMLParser):
    """Every URL-bearing attribute and every ``<script>`` of a document."""

    def __init__(self):
        super().__init__()
        self.refs: list[str] = []
        self.scripts = 0

    def handle_starttag(self, tag, attrs):
        self.scripts += tag == "script"
        for k, v in attrs:
            if k in ("src", "href", "srcset", "poster", "data", "action", "xlink:href") and v:
                self.refs.append(v)


def external_references(text: str) -> list[str]:
    """URLs of the document that are neither ``data:`` nor ``#fragment`` (and scripts)."""
    p = _Refs()
    p.feed(text)
    refs = p.refs + re.findall(r"url\(\s*['\"]?([^'\")]+)", text) + re.findall(
        r"@import\s+['\"]?([^'\";\s]+)", text)
    bad = [r[:80] for r in refs if not (r.startswith("data:") or r.startswith("#"))]
    return bad + (["<script> element"] if p.scripts else [])


# ------------------------------------------------------------------ the browser
def find_browser(given: str | None) -> str | None:
    for name in ([given] if given else []) + list(BROWSERS):
        path = shutil.which(name) or (name if os.path.isfile(name) else None)
        if path:
            return path
    return None


class Pipe:
    """The DevTools protocol over ``--remote-debugging-pipe`` (fd 3 in, fd 4 out)."""

    def __init__(self, browser: str, profile: str):
        to_r, self._to_w = os.pipe()
        self._from_r, from_w = os.pipe()

        def fds():  # in the child: its fd 3 reads our commands, fd 4 writes replies
            a, b = (fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in (to_r, from_w))
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--remote-debugging-pipe", f"--user-data-dir={profile}", "--window-size=1280,900",
             "about:blank"], pass_fds=(3, 4), preexec_fn=fds,  # kept open after fds()
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_r)
        os.close(from_w)
        self._buf, self._id, self.events = b"", 0, []

    def send(self, method: str, params: dict | None = None, session: str | None = None,
             timeout: float = 60.0) -> dict:
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._to_w, json.dumps(msg).encode() + b"\0")
        while True:
            m = self._read(timeout)
            if m.get("id") == self._id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def wait_for(self, method: str, timeout: float = 60.0) -> dict:
        for m in self.events:
            if m.get("method") == method:
                return m
        while True:
            m = self._read(timeout)
            self.events.append(m)
            if m.get("method") == method:
                return m

    def _read(self, timeout: float) -> dict:
        end = time.monotonic() + timeout
        while b"\0" not in self._buf:
            left = end - time.monotonic()
            if left <= 0 or not select.select([self._from_r], [], [], left)[0]:
                raise TimeoutError("the browser did not answer")
            chunk = os.read(self._from_r, 1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed its pipe")
            self._buf += chunk
        raw, self._buf = self._buf.split(b"\0", 1)
        return json.loads(raw)

    def close(self) -> None:
        try:
            self.send("Browser.close", timeout=10)
        except Exception:  # noqa: BLE001 - it may already be gone
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        os.close(self._to_w)
        os.close(self._from_r)


def open_in_browser(browser: str, html: Path, shot: Path) -> list[str]:
    """Load ``html``, return the problems seen, save a 1280 x 900 screenshot."""
    url = html.resolve().as_uri()
    with tempfile.TemporaryDirectory() as profile:
        b = Pipe(browser, profile)
        try:
            target = b.send("Target.createTarget", {"url": "about:blank"})["targetId"]
            sid = b.send("Target.attachToTarget", {"targetId": target, "flatten": True}
                         )["sessionId"]
            for domain in ("Runtime", "Log", "Network", "Page"):
                b.send(f"{domain}.enable", session=sid)
            b.send("Emulation.setDeviceMetricsOverride", {"width": WIDTH, "height": 900,
                   "deviceScaleFactor": 1, "mobile": False}, session=sid)
            b.events.clear()
            b.send("Page.navigate", {"url": url}, session=sid)
            b.wait_for("Page.loadEventFired")
            png = b.send("Page.captureScreenshot", {"format": "png"}, session=sid)["data"]
            shot.write_bytes(base64.b64decode(png))
            title = b.send("Runtime.evaluate", {"expression": "document.title"},
                           session=sid)["result"].get("value", "")
            wide = b.send("Runtime.evaluate", {"expression": WIDEST, "returnByValue": True},
                          session=sid)["result"].get("value")
        finally:
            b.close()
    problems = [] if title.startswith("vhfit report") else [f"page title {title!r}"]
    if wide:  # a horizontal scrollbar at 1280 px
        problems.append(f"wider than a {WIDTH} px window: {wide}")
    for e in b.events:
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            problems.append(f"console error: {p.get('args')}")
        elif m == "Runtime.exceptionThrown":
            problems.append(f"exception: {p.get('exceptionDetails', {}).get('text')}")
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            problems.append(f"log error: {p['entry'].get('text')}")
        elif m == "Network.requestWillBeSent":
            req = p.get("request", {}).get("url", "")
            if req != url and not req.startswith("data:"):
                problems.append(f"request outside the file: {req[:100]}")
        elif m == "Network.loadingFailed":
            problems.append(f"failed to load: {p.get('errorText')}")
    return problems


def demo_report(out: Path) -> list[str]:
    """``vhfit demo`` in-process: its report's size (must be under 3 MB) and write time
    (printed: a time limit would make the check depend on the machine's load)."""
    from vhfit import cli, report

    took = []
    write = report.write_report

    def timed(*a, **kw):
        t0 = time.perf_counter()
        write(*a, **kw)
        took.append(time.perf_counter() - t0)

    report.write_report = timed
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # its table: not this check's
            code = cli.main(["demo", "--out", str(out / "demo"), "--force", "-q"])
    finally:
        report.write_report = write
    path = out / "demo" / "report.html"
    if code != 0 or not path.is_file() or len(took) != 1:
        return [f"vhfit demo: exit {code}, report written {len(took)} time(s)"]
    size = path.stat().st_size
    print(f"demo: report {size / 1e6:.2f} MB, written in {took[0]:.2f} s")
    return [] if size < 3e6 else [f"demo report {size / 1e6:.2f} MB: over 3 MB"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="report-check", help="folder of the reports and shots")
    ap.add_argument("--browser", help="the Chromium binary (default: found on PATH)")
    ap.add_argument("--demo", action="store_true",
                    help="also run vhfit demo and report its report's size and write time")
    args = ap.parse_args(argv)
    browser = find_browser(args.browser)
    if browser is None:
        print("check_report: no Chromium found: apt-get install -y chromium-headless-shell "
              "(or give --browser PATH)", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    failed = 0
    for name, make in (("multi_mode", multi_mode), ("ramp_hold", ramp_hold), ("dma", dma)):
        cal, _ = make()
        path = out / f"{name}.html"
        t0 = time.perf_counter()
        cal.report(path)  # the curves it keeps: at T_ref, as fitted
        took = time.perf_counter() - t0
        text = path.read_text(encoding="utf-8")
        problems = [f"external reference: {r}" for r in external_references(text)]
        problems += open_in_browser(browser, path, out / f"{name}.png")
        size = path.stat().st_size
        print(f"{name}: {size / 1e6:.2f} MB, written in {took:.2f} s, RMSAPE "
              f"{cal.rmsape:.3g} %, screenshot {out / (name + '.png')}: "
              + ("ok" if not problems else "FAILED"))
        for p in problems:
            print(f"  {p}")
        failed += bool(problems)
    if args.demo:
        problems = demo_report(out)
        problems += open_in_browser(browser, out / "demo" / "report.html", out / "demo.png") \
            if not problems else []
        for p in problems:
            print(f"  {p}")
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
