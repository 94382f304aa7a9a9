"""The ParaView plugin's help (routes/paraview_help.py, routes/help_engine.py): a page per
proxy where ParaView 5.11's "?" looks for it, with the property table, from the proxy XML a
Python plugin's decorators write; nothing registered outside the GUI."""

from __future__ import annotations

import os
import sqlite3
import subprocess

from pinn_engine.routes import help_engine, paraview_help

FILTER_XML = """<ServerManagerConfiguration><ProxyGroup name="filters">
<SourceProxy name="PINNThing" label="PINN Thing" class="m.PINNThing">
<Documentation long_help="The long help." short_help="Short help.">The long help.</Documentation>
<InputProperty name="Input" command="AddInputConnection"><Documentation>The curve.</Documentation>
<DataTypeDomain name="input_type"><DataType value="vtkPolyData"/></DataTypeDomain>
</InputProperty>
<IntVectorProperty name="Method" default_values="2" command="P01Method" number_of_elements="1">
<EnumerationDomain name="enum"><Entry value="0" text="pinn"/><Entry value="2" text="tfi"/>
</EnumerationDomain><Documentation>How it is made.</Documentation></IntVectorProperty>
<IntVectorProperty name="GridSize" default_values="41 21" command="P02" number_of_elements="2">
<IntRangeDomain name="range" min="2" max="99"/><Documentation>Nodes.</Documentation>
</IntVectorProperty>
<DoubleVectorProperty name="Angle" label="Face Angle" default_values="40" command="P03">
<DoubleRangeDomain name="range" max="179"/></DoubleVectorProperty>
<StringVectorProperty name="FileName" command="SetFileName" panel_visibility="never"/>
<IntVectorProperty name="IsThreeD" command="GetIsThreeD" information_only="1"/>
</SourceProxy></ProxyGroup></ServerManagerConfiguration>"""
WRITER_XML = """<ServerManagerConfiguration><ProxyGroup name="writers">
<WriterProxy name="ThingWriter" label="ThingWriter" class="m.ThingWriter">
<Hints><WriterFactory extensions="x" file_description="Thing File"/></Hints>
</WriterProxy></ProxyGroup></ServerManagerConfiguration>"""


def test_a_page_per_proxy_named_as_paraview_looks_it_up():
    pages, contents = paraview_help.help_pages([FILTER_XML, WRITER_XML])
    assert [p.name for p in pages] == [
        "index.html",
        "filters.PINNThing.html",
        "writers.ThingWriter.html",
    ]
    # pqHelpReaction::showProxyHelp: qthelp://NS/<NS up to its first dot>/<group>.<name>.html
    assert paraview_help.FOLDER == paraview_help.NAMESPACE.split(".")[0]
    assert paraview_help.NAMESPACE == paraview_help.NAMESPACE.lower()  # a URL's host
    assert [p.title for p in pages[1:]] == ["PINN Thing", "Thing File"]  # a writer: its file type
    assert [e.name for e in contents.children] == [p.name for p in pages[1:]]


def test_the_page_holds_the_property_table_as_the_panel_shows_it():
    page = paraview_help.help_pages([FILTER_XML])[0][1]
    html = page.html
    assert "<title>PINN Thing</title>" in html and "Short help." in html
    assert "The long help." in html
    rows = html.split("<tr>")[1:]
    assert [r.split("</th>")[0].removeprefix("<th>") for r in rows] == [
        "Input",
        "Method",
        "Grid Size",  # the label a property without one is shown with
        "Face Angle",
    ]  # FileName and IsThreeD: not on the panel
    method = rows[1]
    assert "<td>tfi</td>" in method  # the default's text
    assert "<li>pinn</li><li>tfi</li>" in method
    assert "from 2 to 99" in rows[2] and "<td>41 21</td>" in rows[2]
    assert "vtkPolyData" in rows[0] and "at most 179" in rows[3]
    assert set(page.keywords) == {"PINN Thing", "PINNThing"}


def test_outside_the_gui_nothing_is_written_nor_registered(tmp_path, monkeypatch):
    monkeypatch.setattr(help_engine.tempfile, "tempdir", str(tmp_path))
    assert not help_engine.in_gui()
    paraview_help.register_in_gui([FILTER_XML])
    assert help_engine.registered() == [] and list(tmp_path.iterdir()) == []


def test_write_help_gives_a_qch_of_the_pages(tmp_path):
    path = tmp_path / "help.qch"
    paraview_help.write_help(path, [FILTER_XML])
    with sqlite3.connect(path) as db:
        names = [r[0] for r in db.execute("SELECT Name FROM FileNameTable WHERE FolderId=1")]
        namespace = db.execute("SELECT Name FROM NamespaceTable").fetchone()[0]
    assert names == ["index.html", "filters.PINNThing.html"]
    assert namespace == paraview_help.NAMESPACE


def test_the_help_files_of_ended_guis_are_removed(tmp_path):
    ended = subprocess.Popen(["true"])
    ended.wait()
    for pid in (ended.pid, os.getpid()):
        (tmp_path / f"pinn-mesh-help-{pid}.qch").write_bytes(b"")
    (tmp_path / "pinn-mesh-help-notes.qch").write_bytes(b"")
    help_engine._remove_ended(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        f"pinn-mesh-help-{os.getpid()}.qch",
        "pinn-mesh-help-notes.qch",
    ]
