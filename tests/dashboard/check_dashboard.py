#!/usr/bin/python3
"""The coordinator's dashboard (GET / of the status socket) in a real headless browser.

Debian's chromium is driven by chromedriver (Debian's chromium-driver, the same version) over the W3C WebDriver
protocol, spoken here with Python's standard library, so the test needs no network and no other package.

  live        a poet-coordinator with two poet-worker processes on loopback: the page shows the run, its workers
              and its pairs (env names, course pictures, score curves), the iteration it shows increases, the
              tree and score pictures load, the replay canvas draws the walker; then the coordinator is killed
              with SIGKILL and the page shows its error banner with the last data still there, and when the
              coordinator is started again on the same ports the banner goes and the iteration moves on.
  escaping    an ES_ALONE run whose target environment (a CPPN course) and run directory are named with HTML: the
              page shows the names as text, no script of theirs runs and no element of theirs exists; the
              course is drawn and its card says "CPPN terrain".
  screenshot  a full-page PNG of the dashboard of a coordinator already running (--url, --out).

The browser is chromium and chromedriver from PATH (POET_CHROMIUM and POET_CHROMEDRIVER name others).
Exit codes: 0 passed, 1 failed, 77 skipped (chromium or chromedriver missing outside CI; under CI=true that is a
failure).
"""

import argparse
import base64
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import EXIT_SKIP, Failed, Skipped, free_port, missing_tool  # noqa: E402

DEADLINE_S = 240  # the whole check, inside ctest's TIMEOUT
HOSTILE_ENV = '<img src=x onerror="window.__xss=1">'
HOSTILE_DIR = 'run <svg onload="window.__xss2=1"> &amp; "quotes"'
HOSTILE_WORKER = '<b id="injected">worker</b>'

# A small POET run: random θ, short episodes, children admitted at every reproduction (the minimal criterion
# admits any score), so pairs, transfers and retirements come within seconds; far more iterations than the test
# lasts.
LIVE_CONFIG = """mode: POET
seed: 7
iterations: 100000
es { perturbations: 8 }
walker { max_steps: 400 }
poet { mutation_interval: 2 transfer_interval: 2 repro_threshold: -1000 mc_low: -1000 mc_high: 1000
       max_children: 4 max_admitted: 1 active_cap: 4 }
"""

ESCAPING_CONFIG = """mode: ES_ALONE
seed: 1
iterations: 100000
es { perturbations: 4 }
walker { max_steps: 200 }
es_alone { target { encoding { name: %s cppn {
  nodes { id: 0 role: INPUT } nodes { id: 1 role: OUTPUT } nodes { id: 2 activation: SIN bias: 0.1 }
  connections { from_node: 0 to_node: 1 weight: 0.3 } connections { from_node: 0 to_node: 2 weight: 1 }
  connections { from_node: 2 to_node: 1 weight: 0.5 } } } seed: 0 } }
""" % json.dumps(HOSTILE_ENV)  # a JSON string is a valid text-format string here (quotes escaped by \\)


def log(message):
    print(f"[{time.monotonic() - STARTED:6.1f} s] {message}", flush=True)


STARTED = time.monotonic()


def http_json(url, timeout=5):
    with urllib.request.urlopen(url, timeout=timeout) as response:
        return json.loads(response.read())


def wait_for(what, probe, timeout):
    """Calls probe() until it returns a true value (which is returned); Failed after `timeout` seconds."""
    deadline = time.monotonic() + timeout
    last = None
    while True:
        try:
            last = probe()
            if last:
                return last
        except Failed:
            raise
        except Exception as e:  # noqa: BLE001 - a probe that cannot answer yet
            last = f"{type(e).__name__}: {e}"
        if time.monotonic() > deadline:
            raise Failed(f"timed out after {timeout} s waiting for {what} (last: {last!r})")
        time.sleep(0.25)


# ---------------------------------------------------------------------------------------------------------
# processes


class Processes:
    """Children started in their own process groups, with their output in files; all killed at the end."""

    def __init__(self, root):
        self.root = root
        self.children = []

    def start(self, name, argv):
        out = open(os.path.join(self.root, name + ".log"), "ab")
        process = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                   start_new_session=True)
        out.close()
        process.poet_name = name
        self.children.append(process)
        return process

    def log_text(self, name):
        try:
            with open(os.path.join(self.root, name + ".log"), encoding="utf-8", errors="replace") as f:
                return f.read()
        except FileNotFoundError:
            return ""

    def kill(self, process):
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass

    def kill_all(self):
        for process in reversed(self.children):
            self.kill(process)


def status_port(processes, name, process):
    """The port the coordinator's log names in "status: http://127.0.0.1:PORT/status"."""
    def probe():
        if process.poll() is not None:
            raise Failed(f"{name} exited with {process.returncode}:\n{processes.log_text(name)[-3000:]}")
        m = re.search(r"status: http://127\.0\.0\.1:(\d+)/status", processes.log_text(name))
        return int(m.group(1)) if m else None
    return wait_for(f"{name}'s status line", probe, 60)


# ---------------------------------------------------------------------------------------------------------
# the browser


class Browser:
    """Headless chromium through chromedriver: a WebDriver session and the few commands the checks use."""

    @staticmethod
    def tools():
        """chromium and chromedriver; Skipped or Failed (under CI) when one is missing."""
        chromium = os.environ.get("POET_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
        chromedriver = os.environ.get("POET_CHROMEDRIVER") or shutil.which("chromedriver") or "/usr/bin/chromedriver"
        for path, package in ((chromium, "chromium"), (chromedriver, "chromium-driver")):
            if not os.access(path, os.X_OK):
                missing_tool(f"{path} is missing (Debian package {package})")
        return chromium, chromedriver

    def __init__(self, root, processes, width=1400, height=1000):
        chromium, chromedriver = self.tools()
        port = free_port()
        self.base = f"http://127.0.0.1:{port}"
        self.driver = processes.start("chromedriver", [chromedriver, f"--port={port}"])
        wait_for("chromedriver", lambda: self._call("GET", "/status").get("ready"), 30)
        profile = tempfile.mkdtemp(prefix="chromium-", dir=root)
        options = {"binary": chromium,
                   "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                            "--no-first-run", "--disable-extensions", "--hide-scrollbars",
                            "--force-device-scale-factor=1", f"--window-size={width},{height}",
                            f"--user-data-dir={profile}"]}
        caps = {"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": options}}}
        self.session = self._call("POST", "/session", caps, timeout=60)["sessionId"]

    def _call(self, method, path, body=None, timeout=30):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(self.base + path, data=data, method=method,
                                         headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request, timeout=timeout) as response:
                return json.loads(response.read()).get("value")
        except urllib.error.HTTPError as e:
            raise Failed(f"WebDriver {method} {path}: {e.code} {e.read()[:500]!r}") from e

    def command(self, method, path, body=None, timeout=30):
        return self._call(method, f"/session/{self.session}{path}", body, timeout)

    def open(self, url):
        self.command("POST", "/url", {"url": url}, timeout=60)

    def js(self, script, *args):
        """Runs a function body in the page and returns what it returns."""
        return self.command("POST", "/execute/sync", {"script": script, "args": list(args)})

    def screenshot(self, path):
        """A PNG of the whole page, beyond the window's height."""
        size = self.js("return [document.documentElement.scrollWidth, document.documentElement.scrollHeight];")
        shot = self.command("POST", "/goog/cdp/execute", {"cmd": "Page.captureScreenshot", "params": {
            "format": "png", "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": size[0], "height": size[1], "scale": 1}}}, timeout=60)
        with open(path, "wb") as f:
            f.write(base64.b64decode(shot["data"]))

    def close(self):
        try:
            self._call("DELETE", f"/session/{self.session}", timeout=15)
        except Exception:  # noqa: BLE001 - the process group is killed next anyway
            pass


# What the checks read from the page in one call.
PAGE_STATE = """
const text = (id) => { const e = document.getElementById(id); return e ? e.textContent : null; };
const banner = document.getElementById('error-banner');
const cards = [...document.querySelectorAll('[data-pair-id]')];
const canvas = document.getElementById('replay-canvas');
return {
  iteration: text('iteration'), workers: text('workers-count'), runDir: text('run-dir'), state: text('state'),
  annecs: text('annecs'), frontier: text('frontier'), highestLevel: text('highest-level'),
  workerRows: document.querySelectorAll('#workers-table [data-worker-id]').length,
  banner: banner && getComputedStyle(banner).display !== 'none' ? banner.textContent : null,
  cards: cards.map((c) => ({id: c.dataset.pairId, active: c.dataset.active,
    env: c.querySelector('[data-field=env]').textContent, level: c.querySelector('dl dd').textContent,
    visible: c.getBoundingClientRect().height > 0,
    course: c.querySelector('img[data-field=course]').naturalWidth,
    curve: c.querySelectorAll('[data-field=curve] polyline[data-series=score]').length})),
  tree: document.getElementById('tree-img').naturalWidth,
  scores: document.getElementById('scores-img').naturalWidth,
  replayInfo: text('replay-info'), drawn: Number(canvas.dataset.drawn || 0),
  options: [...document.querySelectorAll('#replay-pair option')].map((o) => o.textContent),
  bodyText: document.body.innerText.length,
};
"""

# Pixels of the replay canvas that are not its background colour.
DRAWN_PIXELS = """
const c = document.getElementById('replay-canvas');
const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
let n = 0;
for (let i = 0; i < d.length; i += 4) {
  if (Math.abs(d[i] - 0xdf) + Math.abs(d[i + 1] - 0xe9) + Math.abs(d[i + 2] - 0xf5) > 24) n++;
}
return n;
"""


def page(browser):
    return browser.js(PAGE_STATE)


def as_int(text):
    return int(text) if text and text.strip().isdigit() else None


# ---------------------------------------------------------------------------------------------------------
# the checks


def start_coordinator(processes, args, name, config_text, root, run_dir, listen, status_address, extra=()):
    argv = [args.coordinator, "--run-dir", run_dir, "--quiet", "--listen", listen,
            "--status-address", status_address, "--liveness-ms", "2000", *extra]
    if config_text is not None:
        config = os.path.join(root, name + ".textproto")
        with open(config, "w", encoding="utf-8") as f:
            f.write(config_text)
        argv[1:1] = ["--config", config]
    process = processes.start(name, argv)
    return process, status_port(processes, name, process)


def start_worker(processes, args, name, listen, extra=()):
    return processes.start(name, [args.worker, "--connect", listen, "--threads", "1", *extra])


def check_live(args, root, processes):
    run_dir = os.path.join(root, "run")
    listen = f"tcp://127.0.0.1:{free_port()}"
    coordinator, port = start_coordinator(processes, args, "coordinator", LIVE_CONFIG, root, run_dir, listen,
                                          "127.0.0.1:0")
    for i in range(2):
        start_worker(processes, args, f"worker{i}", listen)
    url = f"http://127.0.0.1:{port}/"
    log(f"coordinator {coordinator.pid} serves {url}; two workers connect to {listen}")

    browser = Browser(root, processes)
    try:
        browser.open(url)
        wait_for("the iteration on the page", lambda: as_int(page(browser)["iteration"]) is not None, 30)
        log("page loaded")

        wait_for("2 workers on the page",
                 lambda: page(browser)["workers"] == "2" and page(browser)["workerRows"] == 2, 60)
        log("2 workers shown")

        def pairs_match():
            shown = page(browser)["cards"]
            served = {str(p["id"]): p["env"] for p in http_json(url + "pairs")["pairs"]}
            good = [c for c in shown if c["visible"] and c["id"] in served and c["env"] == served[c["id"]]]
            return len(good) >= 2 and good
        cards = wait_for("two pair cards with the served env names", pairs_match, 60)
        log(f"pairs shown: {[(c['id'], c['env']) for c in cards]}")

        first = as_int(page(browser)["iteration"])
        seen = [first]

        def moved():
            it = as_int(page(browser)["iteration"])
            if it is not None and it != seen[-1]:
                seen.append(it)
            return len(seen) >= 3
        wait_for(f"the iteration to change twice from {first}", moved, 90)
        if seen != sorted(seen):
            raise Failed(f"the iteration shown went backwards: {seen}")
        log(f"iterations shown: {seen}")
        wait_for("ANNECS in both definitions",
                 lambda: re.fullmatch(r"\d+ / \d+", page(browser)["annecs"] or ""), 30)
        measures = r"\d+\.\d / \d+\.\d / \d+\.\d"
        wait_for("the obstacle frontier, solved and admitted",
                 lambda: re.fullmatch(f"{measures} \\(admitted {measures}\\)", page(browser)["frontier"] or ""), 30)
        level = page(browser)["highestLevel"]
        if level not in ("none", "easy", "challenging", "very challenging", "extremely challenging"):
            raise Failed(f"the hardest level solved reads {level!r}")

        wait_for("the tree and score pictures", lambda: page(browser)["tree"] > 0 and page(browser)["scores"] > 0, 60)
        wait_for("a course picture and a score curve on an active card",
                 lambda: [c for c in page(browser)["cards"] if c["active"] == "true" and c["course"] > 0
                          and c["curve"] > 0], 60)
        log("pictures, course thumbnails and score curves shown")

        card = next(c for c in page(browser)["cards"] if c["active"] == "true")
        browser.js("document.querySelector(`[data-pair-id='${arguments[0]}']`).click();", card["id"])
        wait_for(f"the replay of pair {card['id']}",
                 lambda: (page(browser)["replayInfo"] or "").startswith(f"#{card['id']} {card['env']} "), 60)
        frames = set()

        def advancing():
            frames.add(browser.js("return document.getElementById('replay-canvas').dataset.frame;"))
            return len(frames) >= 5
        wait_for("the replay to show 5 different frames", advancing, 30)
        pixels = browser.js(DRAWN_PIXELS)
        if pixels < 2000:
            raise Failed(f"the replay canvas has only {pixels} pixels drawn on its background")
        log(f"replay of pair {card['id']} plays ({pixels} pixels drawn)")

        before = page(browser)
        coordinator.send_signal(signal.SIGKILL)
        coordinator.wait(timeout=10)
        if coordinator.returncode != -signal.SIGKILL:
            raise Failed(f"the coordinator ended with {coordinator.returncode}, not by SIGKILL")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=2).close()
            raise Failed(f"port {port} still answers after the coordinator died")
        except OSError:
            pass
        log("coordinator killed with SIGKILL")

        banner = wait_for("the error banner", lambda: page(browser)["banner"], 20)
        after = page(browser)
        last = as_int(before["iteration"])
        if "not answering" not in banner or not re.search(r"last seen iteration \d+", banner):
            raise Failed(f"the banner does not say what happened: {banner!r}")
        if len([c for c in after["cards"] if c["visible"]]) < len([c for c in before["cards"] if c["visible"]]):
            raise Failed(f"pair cards vanished: {len(before['cards'])} before, {len(after['cards'])} after")
        if as_int(after["iteration"]) is None or as_int(after["iteration"]) < last or after["bodyText"] < 300:
            raise Failed(f"the last data is not shown: iteration {after['iteration']!r}, {after['bodyText']} "
                         "characters of text")
        log(f"error banner shown: {banner!r}; {len(after['cards'])} cards still shown")

        coordinator, _ = start_coordinator(processes, args, "coordinator-again", None, root, run_dir, listen,
                                           f"127.0.0.1:{port}", ["--resume"])
        wait_for("the banner to go once the coordinator is back", lambda: page(browser)["banner"] is None, 60)
        wait_for("the iteration to move on after the restart",
                 lambda: (as_int(page(browser)["iteration"]) or -1) > as_int(after["iteration"]), 90)
        log(f"recovered: iteration {page(browser)['iteration']}, no banner")
        if args.screenshot:
            browser.screenshot(args.screenshot)
            log(f"screenshot written to {args.screenshot}")
    finally:
        browser.close()


def check_escaping(args, root, processes):
    run_dir = os.path.join(root, HOSTILE_DIR)
    listen = f"tcp://127.0.0.1:{free_port()}"
    coordinator, port = start_coordinator(processes, args, "coordinator", ESCAPING_CONFIG, root, run_dir, listen,
                                          "127.0.0.1:0")
    start_worker(processes, args, "worker", listen, ["--name", HOSTILE_WORKER])
    url = f"http://127.0.0.1:{port}/"
    log(f"coordinator {coordinator.pid} serves {url}")
    browser = Browser(root, processes)
    try:
        browser.open(url)
        # the page with everything drawn: the pair's card and course picture, the replay, the worker
        wait_for("a pair card with its course picture, a worker and the replay",
                 lambda: [c for c in page(browser)["cards"] if c["course"] > 0] and page(browser)["drawn"] > 5
                 and page(browser)["workerRows"] == 1, 60)
        time.sleep(3)  # time for anything injected to load and run
        injected = browser.js("""
            const foreign = (i) => i.getAttribute('src') !== null && !i.getAttribute('src').startsWith('pictures/');
            return {xss: typeof window.__xss, xss2: typeof window.__xss2,
                    elements: document.querySelectorAll('img[src="x"], svg[onload], [onerror], [onload], #injected')
                                .length,
                    foreign: [...document.images].filter(foreign).length};""")
        if injected != {"xss": "undefined", "xss2": "undefined", "elements": 0, "foreign": 0}:
            raise Failed(f"the names were parsed as HTML: {injected}")
        state = page(browser)
        if [c["env"] for c in state["cards"]] != [HOSTILE_ENV]:
            raise Failed(f"the pair's card does not show its name as text: {[c['env'] for c in state['cards']]!r}")
        if state["cards"][0]["level"] != "CPPN terrain":  # its course is a CPPN genome's, drawn like any other
            raise Failed(f"the CPPN course's card shows level {state['cards'][0]['level']!r}, not 'CPPN terrain'")
        wait_for("the replay to show the name as text", lambda: HOSTILE_ENV in (page(browser)["replayInfo"] or ""), 30)
        if state["runDir"] != run_dir:
            raise Failed(f"the run directory is shown as {state['runDir']!r}, not {run_dir!r}")
        if not any(HOSTILE_ENV in o for o in state["options"]):
            raise Failed(f"the replay choices do not show the name: {state['options']!r}")
        addresses = browser.js("return [...document.querySelectorAll('#workers-table [data-worker-id] td')]"
                               ".map((td) => td.textContent);")
        if HOSTILE_WORKER not in addresses:
            raise Failed(f"the worker's name is not shown as text: {addresses!r}")
        log(f"the names are shown as text (card, replay, choices, run directory, worker); nothing injected")
    finally:
        browser.close()


def take_screenshot(args, root, processes):
    browser = Browser(root, processes, width=args.width, height=900)
    try:
        browser.open(args.url)
        wait_for("the pairs", lambda: len(page(browser)["cards"]) > 0, 60)
        if args.pair is not None:
            browser.js("document.querySelector(`[data-pair-id='${arguments[0]}']`).click();", str(args.pair))
            wait_for(f"the replay of pair {args.pair}",
                     lambda: (page(browser)["replayInfo"] or "").startswith(f"#{args.pair} "), 60)
        wait_for("the pictures and the replay",
                 lambda: page(browser)["tree"] > 0 and page(browser)["scores"] > 0 and page(browser)["drawn"] > 0
                 and all(c["course"] > 0 and c["curve"] > 0 for c in page(browser)["cards"] if c["active"] == "true"),
                 120)
        time.sleep(args.settle)  # the walker a little way into its course
        browser.screenshot(args.out)
        log(f"screenshot of {args.url} written to {args.out}")
    finally:
        browser.close()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("check", choices=["live", "escaping", "screenshot"])
    parser.add_argument("--coordinator", help="poet-coordinator (live, escaping)")
    parser.add_argument("--worker", help="poet-worker (live, escaping)")
    parser.add_argument("--screenshot", help="live: a full-page PNG of the page before the coordinator is killed")
    parser.add_argument("--url", help="screenshot: the dashboard's address")
    parser.add_argument("--out", help="screenshot: the PNG to write")
    parser.add_argument("--width", type=int, default=1400, help="screenshot: the window's width")
    parser.add_argument("--pair", type=int, help="screenshot: the pair to replay (default: the page's choice)")
    parser.add_argument("--settle", type=float, default=4, help="screenshot: seconds to wait once all is drawn")
    args = parser.parse_args()

    def interrupted(signum, _frame):
        raise Failed(f"interrupted by signal {signum}")

    def overdue(_signum, _frame):
        raise Failed(f"not done within {DEADLINE_S} s")

    signal.signal(signal.SIGTERM, interrupted)
    signal.signal(signal.SIGINT, interrupted)
    signal.signal(signal.SIGALRM, overdue)
    signal.alarm(DEADLINE_S)
    root = tempfile.mkdtemp(prefix="poet_dashboard_")
    processes = Processes(root)
    try:
        Browser.tools()  # before anything starts
        if args.check == "screenshot":
            if not args.url or not args.out:
                parser.error("screenshot needs --url and --out")
            take_screenshot(args, root, processes)
        else:
            for binary in (args.coordinator, args.worker):
                if not binary or not os.access(binary, os.X_OK):
                    raise Failed(f"not built: {binary!r} (pass --coordinator and --worker)")
            (check_live if args.check == "live" else check_escaping)(args, root, processes)
    except Skipped as e:
        print(f"SKIPPED {args.check}: {e}")
        return EXIT_SKIP
    except Failed as e:
        print(f"FAILED {args.check}: {e}")
        for process in processes.children:
            print(f"--- {process.poet_name} (last lines) ---\n{processes.log_text(process.poet_name)[-1500:]}")
        return 1
    finally:
        signal.alarm(0)
        processes.kill_all()
        shutil.rmtree(root, ignore_errors=True)
    print(f"{args.check}: passed in {time.monotonic() - STARTED:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
