"""MkDocs hook: every link between pages of the site must reach an existing page and, when it names an anchor, an
element with that id. MkDocs 1.4 checks that a linked page exists but not its anchors, so a renamed heading would
leave dead links behind; a warning here fails `mkdocs build --strict`, which the tests run."""

import logging
import posixpath
import re
from html.parser import HTMLParser
from urllib.parse import unquote, urlsplit

log = logging.getLogger("mkdocs.hooks.anchors")

_ids = {}    # page url ("running/") -> the ids in its content
_links = []  # (source page's file, its url, href)


class _Scan(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.hrefs = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name == "id" and value:
                self.ids.add(value)
            elif name == "href" and tag == "a" and value:
                self.hrefs.append(value)


def on_pre_build(config):
    _ids.clear()
    _links.clear()


def on_page_content(html, page, config, files):
    scan = _Scan()
    scan.feed(html)
    _ids[page.url] = scan.ids
    _links.extend((page.file.src_path, page.url, href) for href in scan.hrefs)
    return html


def _target(page_url, href):
    """The site-relative url a relative href reaches from a page, or None for an external or asset link."""
    parts = urlsplit(href)
    if parts.scheme or parts.netloc or href.startswith("/"):
        return None
    if not parts.path:
        return page_url
    base = page_url if page_url.endswith("/") or page_url == "" else posixpath.dirname(page_url) + "/"
    path = posixpath.normpath(posixpath.join(base, unquote(parts.path)))
    if path == ".":
        path = ""
    if parts.path.endswith("/") and path:
        path += "/"
    return path


def on_post_build(config):
    for src, page_url, href in _links:
        fragment = urlsplit(href).fragment
        target = _target(page_url, href)
        if target is None or target not in _ids:
            continue  # an external link, an image or a file; MkDocs itself reports missing pages
        if fragment and unquote(fragment) not in _ids[target]:
            log.warning("%s links to '%s', but '%s' has no anchor '#%s'", src, href, target or "index", fragment)
