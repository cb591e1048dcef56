#!/usr/bin/python3
"""The teaching page (`cbps explain SCENE --html FILE`) as a person sees it: rendered by headless
Chromium (Debian's `chromium`).

  test_teaching_page_browser.py CBPS dom         the DOM Chromium built has every block, the
                                                 scene's row and column labels, the pictures
  test_teaching_page_browser.py CBPS phone|desktop  a screenshot 412 or 1000 pixels wide is
                                                 not blank: many distinct colours, the row
                                                 kinds' colours present, ink on the page
  test_teaching_page_browser.py CBPS svg-text    every text of every picture lies inside its
                                                 picture as Chromium lays it out (a label
                                                 that overflows the left edge loses its
                                                 minus sign), on pages with negative lambda
                                                 (chain) and many rows (pyramid)

Exits 77 (CTest's SKIP_RETURN_CODE) with a message saying so when chromium is not installed.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

SKIP = 77
SCENE = ["v-corner", "--step", "10"]
# Every block of the page by its id (teaching_page_html.cpp), and the equations it opens with.
BLOCKS = ["J", "Minv", "A", "spectrum", "v1", "system-1", "svg-J", "svg-A", "svg-spectrum",
          "svg-lambda-1", "svg-residual-1", "table-J", "table-A", "table-Minv", "table-b-1",
          "table-lambda-1", "table-v1", "table-v2-1"]
EQUATIONS = ["A = J M⁻¹ Jᵀ (6.2.9)", "(12.3.1)", "w = Aλ − b (6.2)", "(6.1.2)"]
# svg-text: pages whose pictures have long or negative labels. The chain's lambda are all
# negative (its joints pull); the pyramid's picture is binned, one panel per row kind.
SVG_TEXT_SCENES = [["chain", "--step", "30"], ["pyramid", "--step", "5"], SCENE]
# Added to a copy of the page (the page itself has no script): for every <text> of every <svg>,
# how far its laid-out box reaches past the picture's box, in CSS pixels, into <pre id=...>.
MEASURE = """<script>
(function () {
  var out = [];
  document.querySelectorAll("svg").forEach(function (svg) {
    var s = svg.getBoundingClientRect();
    svg.querySelectorAll("text").forEach(function (t) {
      var b = t.getBoundingClientRect();
      out.push({svg: svg.id, text: t.textContent, left: s.left - b.left, right: b.right - s.right,
                top: s.top - b.top, bottom: b.bottom - s.bottom});
    });
  });
  var pre = document.createElement("pre");
  pre.id = "svg-text-overflow";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
})();
</script>"""
# The row kinds' colours (kind_colour in teaching_page_html.cpp): v-corner has contact rows.
CONTACT_RGB = (0xc6, 0x28, 0x28)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def chromium():
    path = shutil.which("chromium")
    if path is None:
        print("SKIPPED: chromium is not installed (Debian package `chromium`, see "
              "scripts/setup.sh); the page's HTML is still checked by the C++ tests")
        sys.exit(SKIP)
    return path


def run_chromium(browser, work, *args):
    # A profile folder of its own, so that two runs at once (ctest -j2) do not share a lock.
    profile = tempfile.mkdtemp(dir=work, prefix="profile-")
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
           "--user-data-dir=" + profile, *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        fail("chromium exited %d: %s" % (r.returncode, r.stderr[-2000:]))
    return r.stdout


def check_dom(cbps, browser, page, work):
    dom = run_chromium(browser, work, "--dump-dom", "file://" + page)
    if "<body" not in dom:
        fail("chromium's DOM has no body")
    missing = [b for b in BLOCKS if 'id="%s"' % b not in dom]
    if missing:
        fail("blocks missing from the rendered DOM: " + ", ".join(missing))
    missing = [e for e in EQUATIONS if e not in dom]
    if missing:
        fail("equations missing from the rendered DOM: " + ", ".join(missing))
    # The labels cbps explain --json gives, every one in the rendered page.
    e = json.loads(subprocess.run([cbps, "explain", *SCENE, "--json"], capture_output=True,
                                  text=True, check=True).stdout)
    labels = e["row_labels"] + e["column_labels"]
    missing = [label for label in labels if label not in dom]
    if missing:
        fail("labels missing from the rendered DOM: " + ", ".join(missing))
    print("dom: %d blocks, %d equations, %d labels found in %d characters of DOM"
          % (len(BLOCKS), len(EQUATIONS), len(labels), len(dom)))


def check_screenshot(browser, page, work, width, height):
    import numpy as np
    import matplotlib.image as mpimg
    png = os.path.join(work, "page-%dx%d.png" % (width, height))
    run_chromium(browser, work, "--hide-scrollbars", "--screenshot=" + png,
                 "--window-size=%d,%d" % (width, height), "file://" + page)
    if not os.path.exists(png):
        fail("chromium wrote no screenshot " + png)
    image = mpimg.imread(png)  # floats in [0, 1], height x width x 3 or 4
    rgb = np.round(image[:, :, :3] * 255).astype(np.int64)
    if rgb.shape[0] != height or rgb.shape[1] != width:
        fail("screenshot is %dx%d, asked for %dx%d" % (rgb.shape[1], rgb.shape[0], width, height))
    colours = len(np.unique(rgb[:, :, 0] * 65536 + rgb[:, :, 1] * 256 + rgb[:, :, 2]))
    ink = float(np.mean(np.any(rgb < 200, axis=2)))  # pixels clearly darker than the paper
    contact = int(np.sum(np.all(np.abs(rgb - np.array(CONTACT_RGB)) <= 8, axis=2)))
    print("screenshot %dx%d: %d distinct colours, %.1f%% ink, %d pixels of the contact colour"
          % (width, height, colours, 100 * ink, contact))
    if colours < 50:
        fail("the screenshot has %d distinct colours: blank or unstyled" % colours)
    if ink < 0.02:
        fail("the screenshot is nearly empty (%.2f%% ink)" % (100 * ink))
    if contact < 20:
        fail("the contact rows' colour is missing from the screenshot (%d pixels)" % contact)


def check_svg_text(cbps, browser, work):
    import html
    import re
    texts = 0
    for scene in SVG_TEXT_SCENES:
        page = os.path.join(work, "page.html")
        subprocess.run([cbps, "explain", *scene, "--html", page], check=True,
                       stdout=subprocess.DEVNULL)
        with open(page, encoding="utf-8") as f:
            text = f.read()
        measured = os.path.join(work, "measured.html")
        with open(measured, "w", encoding="utf-8") as f:
            f.write(text.replace("</body>", MEASURE + "</body>"))
        dom = run_chromium(browser, work, "--window-size=1000,1000", "--dump-dom",
                           "file://" + measured)
        m = re.search(r'<pre id="svg-text-overflow">(.*?)</pre>', dom, re.S)
        if m is None:
            fail("%s: the measuring script wrote nothing" % " ".join(scene))
        boxes = json.loads(html.unescape(m.group(1)))
        if not boxes:
            fail("%s: no text in the pictures" % " ".join(scene))
        # Half a pixel for the layout's rounding.
        out = [b for b in boxes if max(b["left"], b["right"], b["top"], b["bottom"]) > 0.5]
        if out:
            fail("%s: text outside its picture (px past the left, right, top, bottom edge): %s"
                 % (" ".join(scene), "; ".join("%s %r %.1f %.1f %.1f %.1f" % (
                     b["svg"], b["text"], b["left"], b["right"], b["top"], b["bottom"])
                     for b in out[:10])))
        texts += len(boxes)
    print("svg-text: %d texts in the pictures of %d pages, every one inside its picture"
          % (texts, len(SVG_TEXT_SCENES)))


def main():
    if len(sys.argv) != 3 or sys.argv[2] not in ("dom", "phone", "desktop", "svg-text"):
        print(__doc__)
        return 2
    cbps, mode = sys.argv[1], sys.argv[2]
    browser = chromium()
    with tempfile.TemporaryDirectory(prefix="cbps-teaching-page-") as work:
        if mode == "svg-text":
            check_svg_text(cbps, browser, work)
            return 0
        page = os.path.join(work, "page.html")
        subprocess.run([cbps, "explain", *SCENE, "--html", page], check=True,
                       stdout=subprocess.DEVNULL)
        if mode == "dom":
            check_dom(cbps, browser, page, work)
        elif mode == "phone":
            check_screenshot(browser, page, work, 412, 900)
        else:
            check_screenshot(browser, page, work, 1000, 1000)
    return 0


if __name__ == "__main__":
    sys.exit(main())
