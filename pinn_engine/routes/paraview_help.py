"""The ParaView plugin's help: a page per proxy, made from the proxy's own XML (its
documentation and each property's label, documentation, default and domain) in the layout
of ParaView's own filters' pages, written as Qt compressed help (``io.qch``) and registered
with the running GUI's help engine (``help_engine``).

ParaView 5.11's "?" of the Properties panel (``pqHelpReaction::showProxyHelp``) opens
``qthelp://<namespace>/<namespace up to its first dot>/<group>.<proxy name>.html`` of the
first registered .qch that holds it; the pages are named so."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from functools import partial
from html import escape
from pathlib import Path

from pinn_engine.io.qch import Entry, Page, write_qch
from pinn_engine.routes import help_engine

NAMESPACE = "pinn-mesh.paraview"  # lower case: Qt reads it as a URL's host
FOLDER = NAMESPACE.split(".")[0]  # ParaView looks pages up in the folder named so
INDEX = "index.html"
TITLE = "PINN Mesh plugin"  # the help's entry in ParaView's Contents
_PROPERTIES = ("IntVectorProperty", "DoubleVectorProperty", "StringVectorProperty")
_HIDDEN = "never"  # a property's panel_visibility when the panel never shows it


def _text(element) -> str:
    """An element's text, its whitespace collapsed."""
    return " ".join("".join(element.itertext()).split()) if element is not None else ""


def _pretty(name: str) -> str:
    """A property's panel label when its XML gives none ("GridSize": "Grid Size")."""
    out = name[:1]
    for previous, char in zip(name, name[1:]):
        out += (" " if char.isupper() and previous.islower() else "") + char
    return out


def _restrictions(prop) -> str:
    """What the property accepts, in the words of ParaView's own help pages."""
    parts = []
    for domain in prop:
        if domain.tag == "EnumerationDomain":
            items = "".join(f"<li>{escape(e.get('text', ''))}</li>" for e in domain.iter("Entry"))
            parts.append(f"<p>The value can be one of the following:<ul>{items}</ul></p>")
        elif domain.tag == "BooleanDomain":
            parts.append("<p>Accepts boolean values (0 or 1).</p>")
        elif domain.tag in ("IntRangeDomain", "DoubleRangeDomain"):
            low, high = domain.get("min"), domain.get("max")
            if low is not None and high is not None:
                parts.append(f"<p>The value must be from {low} to {high}.</p>")
            elif low is not None:
                parts.append(f"<p>The value must be at least {low}.</p>")
            elif high is not None:
                parts.append(f"<p>The value must be at most {high}.</p>")
        elif domain.tag == "DataTypeDomain":
            kinds = "".join(
                f"<li>{escape(d.get('value', ''))}</li>" for d in domain.iter("DataType")
            )
            parts.append(f"<p>Accepts input of following types:<ul>{kinds}</ul></p>")
    return "".join(parts)


def _default(prop) -> str:
    """The default as the panel shows it: an enumeration's text, else the values."""
    values = prop.get("default_values", "")
    entries = {e.get("value"): e.get("text") for e in prop.iter("Entry")}
    return escape(entries.get(values, values))


def _row(prop) -> str:
    label = prop.get("label") or _pretty(prop.get("name", ""))
    doc = escape(_text(prop.find("Documentation")))
    return (
        f"<tr><th>{escape(label)}</th><td>{doc}</td><td>{_default(prop)}</td>"
        f"<td>{_restrictions(prop)}</td></tr>"
    )


def _title(proxy) -> str:
    """The name a user knows the proxy by: its label, or a writer's file type."""
    factory = proxy.find("Hints/WriterFactory")
    if proxy.get("label", proxy.get("name")) == proxy.get("name") and factory is not None:
        return factory.get("file_description", proxy.get("name"))
    return proxy.get("label") or proxy.get("name")


def proxy_page(group: str, proxy) -> Page:
    """The help page of one proxy element of group ``group``: ParaView's layout (title, short
    help, description, then Property, Description, Default(s), Restrictions)."""
    name, title = proxy.get("name"), _title(proxy)
    doc = proxy.find("Documentation")
    short = doc.get("short_help", "") if doc is not None else ""
    long = doc.get("long_help") or _text(doc) if doc is not None else ""
    rows = "".join(
        _row(prop)
        for prop in proxy
        if (prop.tag in _PROPERTIES or prop.tag == "InputProperty")
        and prop.get("panel_visibility") != _HIDDEN
        and prop.get("information_only") != "1"
    )
    html = (
        f"<html><head><title>{escape(title)}</title></head><body>"
        f"<h2>{escape(title)} ({escape(name)})</h2><i><p>{escape(short)}</p></i>"
        f'<div class="description">{escape(long)}</div>'
        '<table width="97%" border="2px"><tr bgcolor="#9acd32"><th>Property</th>'
        '<th width="60%">Description</th><th width="5%">Default(s)</th>'
        f'<th width="20%">Restrictions</th></tr>{rows}</table></body></html>'
    )
    return Page(f"{group}.{name}.html", title, html, keywords=(title, name))


def help_pages(xmls: list[str]) -> tuple[list[Page], Entry]:
    """The pages of the proxies in ``xmls`` (a Python plugin's XML, one string a proxy),
    an index page first, and the table of contents."""
    pages = []
    for xml in xmls:
        for group in ET.fromstring(xml).iter("ProxyGroup"):
            pages += [proxy_page(group.get("name"), proxy) for proxy in group]
    unique = list({page.title: page for page in reversed(pages)}.values())[::-1]
    links = "".join(f'<li><a href="{p.name}">{escape(p.title)}</a></li>' for p in unique)
    index = Page(
        INDEX,
        TITLE,
        f"<html><head><title>{TITLE}</title></head><body><h2>{TITLE}</h2>"
        "<p>Structured meshes from a physics-informed neural network: filters in "
        "Filters &gt; Mesh Generation (Ctrl+Space, then PINN, PINN multi or PINN hex), the "
        "Airfoil source and reader, and the PINN Mesh writers of File &gt; Save Data. The "
        f"guides are in the docs/ folder of the pinn-mesh checkout.</p><ul>{links}</ul>"
        "</body></html>",
        keywords=(TITLE,),
    )
    contents = Entry(TITLE, INDEX, [Entry(p.title, p.name) for p in unique])
    return [index, *pages], contents


def write_help(path: Path, xmls: list[str]) -> None:
    """The help of the proxies in ``xmls`` as the .qch ``path``."""
    pages, contents = help_pages(xmls)
    write_qch(path, NAMESPACE, FOLDER, pages, contents)


def register_in_gui(xmls: list[str]) -> None:
    """Register the help of the proxies in ``xmls`` with the ParaView GUI this runs in (none
    in pvpython, pvbatch or a server)."""
    help_engine.register(partial(write_help, xmls=xmls))
