"""ParaView plugin: Filters > Mesh Generation > PINN Structured Mesh, PINN Structured Mesh
(Multi-Block) and PINN Structured Mesh (Hexahedral); the last two keep their old Python names,
PINNMultiBlockMesh and PINNHexahedralMesh, out of the menus (``_mesh_filter``).

A thin layer of ``paraview.util.vtkAlgorithm`` decorators over
``pinn_engine.routes.algorithm.PinnMeshAlgorithm``,
``pinn_engine.routes.multiblock_algorithm.PinnMultiBlockAlgorithm`` and
``pinn_engine.routes.hexa_algorithm.PinnHexaAlgorithm``. Load it with Tools >
Manage Plugins > Load New (this file) or put this folder on ``PV_PLUGIN_PATH``.
``pinn_engine`` is imported from the checkout this file lives in (``plugin/..``); it need not
be installed into ParaView's Python,
but that Python needs numpy, scipy, scikit-learn and (for training) torch: start ParaView
with ``scripts/pvenv.sh paraview`` (which also puts the ``getargspec`` shim that Debian's
ParaView 5.11 needs on PYTHONPATH; see README).

It also registers File > Save Data writers for the filter's output (``pinn_engine.io.export``):
PLOT3D, CGNS with boundary conditions, SU2, Gmsh 4.1 and OpenFOAM, each using the grid's
Patch Names (docs/export.md).

The panels of the mesh filters, the blockMeshDict reader and the Airfoil source are
generated: each property of ``pinn_engine.routes.panel.PANELS``
(its name, label, default, range, choices, help and the algorithm's method it sets, with
the labels of ``routes.names`` and the ranges and defaults of the constraint table) becomes
one decorated method (``_panel``, ``_property``). Property order: ParaView 5.11 lists a
Python plugin's properties alphabetically by method name, so the methods carry a numeric
prefix (``P01...``) that keeps the panel in the intended order in every version. Each
property and input is one call of a helper (``_intvector``, ``_polyline_input``, ...) that
applies ParaView's decorator stack in its fixed order (``_stack``), so the plugin's XML is
what the stacks written out would give.
"""

import os
import sys
from functools import partial
from xml.etree import ElementTree as ET
from xml.sax.saxutils import escape, quoteattr

_REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if _REPO not in sys.path:
    sys.path.insert(0, _REPO)

try:
    from pinn_engine import __version__
    from pinn_engine.io.export import FORMATS
    from pinn_engine.io.export.algorithm import PARAVIEW_FORMATS, GridWriter
    from pinn_engine.routes.airfoil_algorithm import AirfoilReader, AirfoilSource
    from pinn_engine.routes.algorithm import PinnMeshAlgorithm
    from pinn_engine.routes.dictionary_algorithm import PinnBlockMeshDictReader
    from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm
    from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
    from pinn_engine.routes.panel import PANELS
    from pinn_engine.routes.paraview_help import register_in_gui
except ImportError as _exc:  # a clear line in ParaView's output instead of a bare traceback
    raise ImportError(
        f"PINN Structured Mesh plugin: cannot import pinn_engine from {_REPO} ({_exc}); keep "
        "this file in the plugin/ folder of a pinn-mesh checkout and give ParaView's Python "
        "numpy, scipy and scikit-learn (see scripts/pvenv.sh)"
    ) from _exc

from paraview.detail.pythonalgorithm import get_plugin_xmls  # noqa: E402
from paraview.util.vtkAlgorithm import smdomain, smhint, smproperty, smproxy  # noqa: E402

try:  # the client side, where displays are made (absent from a data-server-only build)
    from paraview.modules.vtkRemotingServerManager import (
        vtkSMPropertyHelper,
        vtkSMProxyManager,
    )
    from paraview.modules.vtkRemotingViews import vtkSMPVRepresentationProxy
    from vtkmodules.vtkCommonDataModel import vtkDataObject
except ImportError:
    vtkSMProxyManager = None

paraview_plugin_name = "PINN Mesh"
paraview_plugin_version = __version__

_COLOUR_ARRAY = "MaxIncludedAngle"  # what a new grid is coloured by
_MESH_FILTERS = set()  # whose displays get that colour: the proxy names _mesh_filter made
_OLD_NAMES = []  # (old proxy name, its definition): the filters' old names (_mesh_filter)
_MENU = '<ShowInMenu category="Mesh Generation"/>'  # where the filters and the Airfoil source are
_OBSERVERS = []  # the display observers (_ColourWhenDataArrives)
# id(session proxy manager): (it, its RegisterEvent observer, the observer's id); VTK's own
# reference to a Python observer was not enough in the GUI (a closure crashed on its 2nd call)
_WATCHED_SESSIONS = {}
_TWO_D_INPUT = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="IsThreeD" value="0"/>'
)  # writer settings that only a 2D grid has (a hexahedral grid is not extruded)
CGNS_FIRST = "CGNSPINNMeshWriter"  # sorts before ParaView's CGNSWriter (see the writers below)


class _ColourWhenDataArrives:
    """Observer of one display of a PINN mesh filter. When the filter's output first has
    cells: colour the display by MaxIncludedAngle if it is in a solid colour, and hide the
    filter's inputs in its view. ParaView picks a display's colour once, when it creates the
    display, from the data it has then: an empty output (a failed first Apply) carries no
    arrays, and a 3D structured grid came up in Solid Color. The filters ask ParaView not to
    hide their inputs on Apply (``<Visibility replace_input="0"/>``) so that a failed Apply
    leaves the input in view; the inputs are hidden here once there is a grid to show
    instead."""

    def __init__(self):
        self.settled = False  # (removing an observer inside its own call crashes the GUI)

    def __call__(self, repr_proxy, event):
        if self.settled:
            return
        source = vtkSMPropertyHelper(repr_proxy, "Input").GetAsProxy()
        if source is None:
            return
        info = source.GetDataInformation(vtkSMPropertyHelper(repr_proxy, "Input").GetOutputPort())
        if info.GetNumberOfCells() == 0:
            return
        self.settled = True  # from here on, the colour and what is shown are the user's
        if (
            not vtkSMPVRepresentationProxy.GetUsingScalarColoring(repr_proxy)
            and info.GetCellDataInformation().GetArrayInformation(_COLOUR_ARRAY) is not None
        ):
            vtkSMPVRepresentationProxy.SetScalarColoring(
                repr_proxy, _COLOUR_ARRAY, vtkDataObject.FIELD_ASSOCIATION_CELLS
            )
            vtkSMPVRepresentationProxy.RescaleTransferFunctionToDataRange(repr_proxy, False, False)
            repr_proxy.UpdateVTKObjects()
        _hide_inputs(source, repr_proxy)


def _hide_inputs(source, repr_proxy):
    """Hide the displays of ``source``'s inputs in the view that holds ``repr_proxy``."""
    pxm = source.GetSessionProxyManager()
    inputs = {
        vtkSMPropertyHelper(source, name).GetAsProxy(k).GetGlobalID()
        for name in ("Input", "BlockEdges", "AuxiliaryLines")
        if source.GetProperty(name) is not None
        for k in range(vtkSMPropertyHelper(source, name).GetNumberOfElements())
        if vtkSMPropertyHelper(source, name).GetAsProxy(k) is not None
    }
    for k in range(pxm.GetNumberOfProxies("views")):
        view = pxm.GetProxy("views", pxm.GetProxyName("views", k))
        shown = vtkSMPropertyHelper(view, "Representations")
        members = [shown.GetAsProxy(n) for n in range(shown.GetNumberOfElements())]
        if repr_proxy not in members:
            continue
        for other in members:
            if other is None or other.GetProperty("Input") is None:
                continue
            upstream = vtkSMPropertyHelper(other, "Input").GetAsProxy()
            if upstream is not None and upstream.GetGlobalID() in inputs:
                vtkSMPropertyHelper(other, "Visibility").Set(0)
                other.UpdateVTKObjects()


def _watch_displays():
    """Let every new display of a PINN mesh filter (``_MESH_FILTERS``) in the active session be
    coloured by MaxIncludedAngle when its first grid arrives (``_ColourWhenDataArrives``).
    Runs where proxies are made (the GUI, pvpython); idempotent per session."""
    if vtkSMProxyManager is None:
        return
    pxm = vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
    if pxm is None or id(pxm) in _WATCHED_SESSIONS:
        return
    seen = set()

    def on_register(obj, event):
        for k in range(pxm.GetNumberOfProxies("representations")):
            proxy = pxm.GetProxy("representations", pxm.GetProxyName("representations", k))
            if proxy is None or proxy.GetGlobalID() in seen:
                continue
            seen.add(proxy.GetGlobalID())
            if proxy.GetProperty("Input") is None or proxy.GetProperty("ColorArrayName") is None:
                continue
            source = vtkSMPropertyHelper(proxy, "Input").GetAsProxy()
            if source is not None and source.GetXMLName() in _MESH_FILTERS:
                observer = _ColourWhenDataArrives()
                _OBSERVERS.append(observer)  # kept alive here, not only by VTK
                proxy.AddObserver("UpdateDataEvent", observer)

    _WATCHED_SESSIONS[id(pxm)] = (pxm, on_register, pxm.AddObserver("RegisterEvent", on_register))


def _enum(options):
    entries = "".join(f'<Entry value="{k}" text="{name}"/>' for k, name in enumerate(options))
    return f'<EnumerationDomain name="enum">{entries}</EnumerationDomain>'


def _doc(text):
    return f"<Documentation>{text}</Documentation>"


def _proxy_doc(short, text):
    """A proxy's documentation: ``short`` (a line) and ``text`` for the panel's "?" help."""
    return (
        f"<Documentation long_help={quoteattr(text)} short_help={quoteattr(short)}>"
        f"{escape(text)}</Documentation>"
    )


def _stack(*decorators):
    """One decorator doing what ``decorators`` written one above the other in this order do
    (the bottom one first: the order ParaView's XML takes them in); a None entry stands for
    a part the declaration leaves out."""

    def decorate(target):
        for decorator in reversed(decorators):
            if decorator is not None:
                target = decorator(target)
        return target

    return decorate


def _vector_property(
    vector, range_domain, *, doc, bounds=None, enum=None, inline_domain="", hint=None, **attrs
):
    """A panel property's whole decorator stack: the ``vector`` property with ParaView's
    ``attrs`` (name, label, default_values, panel_visibility), its ``range_domain`` over
    ``bounds`` (min, max) or its ``enum`` options, its ``doc`` with ``inline_domain`` (a
    domain's XML written in the same element, ahead of the Documentation) and a visibility
    ``hint``."""
    return _stack(
        vector(**attrs),
        None if bounds is None else range_domain(**bounds),
        None if enum is None else smdomain.xml(_enum(enum)),
        smdomain.xml(inline_domain + _doc(doc)),
        None if hint is None else smhint.xml(hint),
    )


_intvector = partial(_vector_property, smproperty.intvector, smdomain.intrange)
_doublevector = partial(_vector_property, smproperty.doublevector, smdomain.doublerange)
_stringvector = partial(_vector_property, smproperty.stringvector, None)


def _polyline_input(*, doc, optional=False, **attrs):
    """A vtkPolyData input port with ParaView's ``attrs``; a repeatable one's clean_command
    must disconnect that port only (the decorator's default, RemoveAllInputs, would
    disconnect the other ports too)."""
    return _stack(
        smproperty.input(**attrs),
        smdomain.datatype(dataTypes=["vtkPolyData"], composite_data_supported=False),
        smdomain.xml(_doc(doc)),
        smhint.xml("<Optional/>") if optional else None,
    )


def _field_input(port_index):
    """The optional Field input of SPEC 14 at ``port_index``: any dataset (a solver's
    result: connect the OpenFOAM reader's output), whose arrays Field Array lists."""
    return _stack(
        smproperty.input(name="Field", label="Field", port_index=port_index),
        smdomain.datatype(dataTypes=["vtkDataObject"], composite_data_supported=True),
        smdomain.xml(
            '<InputArrayDomain name="field_arrays" attribute_type="any-except-field" optional="1"/>'
            + _doc(
                "Optional: a solution on this domain (any dataset: connect the OpenFOAM "
                "reader's or another reader's output). The grid's nodes then move to where "
                "Field Array changes fast, its counts, corners and patches kept."
            )
        ),
        smhint.xml("<Optional/>"),
    )


# The Field Array and Adapt Strength properties of the 2D filters (SPEC 14)
_FIELD_ARRAY = """
<StringVectorProperty name="FieldArray" label="Field Array" command="SetAdaptArray"
    number_of_elements="5" element_types="0 0 0 0 2" animateable="0">
  <ArrayListDomain name="array_list" attribute_type="Scalars" input_domain_name="field_arrays">
    <RequiredProperties><Property name="Field" function="Input"/></RequiredProperties>
  </ArrayListDomain>
  <Documentation>The array of the Field input the grid is adapted to: a point or cell
  array, a vector (velocity) by its magnitude.</Documentation>
</StringVectorProperty>"""


def _field_array(cls):
    """Field Array on a 2D filter's panel (its Adapt Strength is in ``PANELS``)."""

    @smproperty.xml(_FIELD_ARRAY)
    def P90FieldArray(self, *selection):
        self.SetAdaptArray(*selection)

    cls.P90FieldArray = P90FieldArray
    return cls


_VECTORS = {"int": _intvector, "double": _doublevector, "string": _stringvector}


def _property(prop):
    """The decorated method of one panel property (``routes.panel.Property``): its values,
    each by ``prop.convert``, to the algorithm's ``prop.call`` after ``prop.before``."""

    def method(self, *values):
        getattr(self, prop.call)(*prop.before, *map(prop.convert, values))

    method.__name__ = method.__qualname__ = prop.method  # the property's command
    attrs = {
        "name": prop.name,
        "label": prop.shown,
        "default_values": prop.default,
        "number_of_elements": len(prop.default) if isinstance(prop.default, list) else 1,
        "panel_visibility": "advanced" if prop.advanced else None,
    }
    if prop.files:
        extensions, description = prop.files
        return _stack(
            smproperty.stringvector(**attrs),
            smdomain.filelist(),
            smhint.filechooser(extensions=extensions, file_description=description),
            smdomain.xml(_doc(prop.doc)),
        )(method)
    vector = _VECTORS[prop.vector]
    check_box = '<BooleanDomain name="bool"/>' if prop.boolean else ""
    return vector(
        bounds=prop.bounds,
        enum=prop.enum,
        hint=prop.hint,
        doc=prop.doc,
        inline_domain=check_box,
        **attrs,
    )(method)


def _panel(kind):
    """The properties of ``kind``'s panel (``routes.panel.PANELS``): a mesh filter's, the
    blockMeshDict reader's or the Airfoil source's."""

    def decorate(cls):
        for prop in PANELS[kind]:
            setattr(cls, prop.method, _property(prop))
        return cls

    return decorate


def _mesh_filter(*inputs, names, summary, doc):
    """A filter in Filters > Mesh Generation whose grid is shown with its cells' edges: its
    ``inputs`` (``_polyline_input``, in port order) and its panel help (``_proxy_doc``).
    ``names`` are (proxy name, label) pairs: the first names the filter of the menus and the
    quick launch; each further one an old name that scripts and saved states keep using, the
    same filter under that name and label but in neither (``_OLD_NAMES``)."""
    (name, label), *old_names = names

    def decorate(cls):
        _MESH_FILTERS.update(n for n, _ in names)
        proxy = _stack(
            # support_reload=False: no developer's "Reload Python Module" button
            smproxy.filter(name=name, label=label, support_reload=False),
            smhint.xml(_MENU),
            smhint.xml('<RepresentationType view="RenderView" type="Surface With Edges"/>'),
            # the inputs stay shown until a grid arrives (_ColourWhenDataArrives hides them)
            smhint.xml('<Visibility replace_input="0"/>'),
            *reversed(inputs),
            smproperty.xml(_proxy_doc(summary, doc)),
        )(cls)
        (xml,) = get_plugin_xmls({name: proxy})
        _OLD_NAMES.extend((old, _old_name_xml(xml, old, text, label)) for old, text in old_names)
        return proxy

    return decorate


def _old_name_xml(xml, name, label, new_label):
    """The definition ``xml`` (a filter's ServerManagerConfiguration) under the old ``name``
    and ``label`` (its Python name in ``paraview.simple``), without the ShowInMenu hint; its
    short help names the filter's label now, ``new_label``."""
    root = ET.fromstring(xml)
    proxy = root.find("ProxyGroup/SourceProxy")
    proxy.set("name", name)
    proxy.set("label", label)
    hints = proxy.find("Hints")
    for hint in hints.findall("ShowInMenu"):
        hints.remove(hint)
    proxy.find("Documentation").set(
        "short_help", f"The old name of {new_label}, kept for scripts and saved states."
    )
    return ET.tostring(root, encoding="unicode")


def _define_old_names(*_):
    """Define the filters' old names (``_OLD_NAMES``) in the active session, once a session.
    ParaView 5.11 gives every source and filter of a plugin's XML the ShowInMenu hint (so
    they are in the Filters menu and the quick launch); loaded here by themselves, as
    ParaView's own definitions are, they get none. Runs at load and at each new session
    (``ActiveSessionChanged``: a plugin on PV_PLUGIN_PATH loads before the first one)."""
    if vtkSMProxyManager is None:
        return
    pxm = vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
    if pxm is None:
        return
    definitions = pxm.GetProxyDefinitionManager()
    for name, xml in _OLD_NAMES:
        if not definitions.HasDefinition("filters", name):
            definitions.LoadConfigurationXMLFromString(xml)


@_mesh_filter(
    _polyline_input(
        name="Input",
        port_index=0,
        multiple_input=True,
        clean_command="RemoveAllBoundaryInputs",
        doc="The closed boundary: one closed polyline or polygon with four corners. "
        "Select it together with sources of open auxiliary lines and apply the "
        "filter: the closed curve is taken as the boundary, the open ones as "
        "auxiliary lines.",
    ),
    _polyline_input(
        name="AuxiliaryLines",
        label="Auxiliary Lines",
        port_index=1,
        multiple_input=True,
        clean_command="RemoveAllAuxiliaryLines",
        optional=True,
        doc="Optional open polylines from one side of the boundary to the opposite "
        "side (several polylines per input and several inputs both work). Used "
        "by the pinn method only.",
    ),
    _field_input(2),
    names=[("PINNStructuredMesh", "PINN Structured Mesh")],
    summary="Structured quadrilateral grid from a physics-informed neural network.",
    doc="Structured quadrilateral grid of a four-sided 2D domain from a "
    "physics-informed neural network (pinn), with MGNet, transfinite "
    "interpolation and elliptic baselines, or an O- or C-grid around an airfoil "
    "(Topology). Input: the closed boundary with four corners, optionally with "
    "open auxiliary lines between opposite sides. Cells carry their included "
    "angles (MaxIncludedAngle, MinIncludedAngle), ScaledJacobian and Folded; "
    "field data the report and the loss history. A training ends after Time "
    "Limit seconds or at pkill -USR1 -x paraview with its best grid so far. "
    "Guide: docs/routes.md of the pinn-mesh checkout.",
)
@_field_array
@_panel("four-sided")
class PINNStructuredMesh(PinnMeshAlgorithm):
    """The ParaView face of :class:`pinn_engine.routes.algorithm.PinnMeshAlgorithm`."""

    def __init__(self):
        super().__init__()
        _watch_displays()  # a session made after the plugin was loaded

    def RemoveAllBoundaryInputs(self):
        # clean commands of the two repeatable inputs (_polyline_input)
        self.RemoveAllInputConnections(0)

    def RemoveAllAuxiliaryLines(self):
        self.RemoveAllInputConnections(1)


@_mesh_filter(
    _polyline_input(
        name="Input",
        port_index=0,
        multiple_input=True,
        clean_command="RemoveAllBoundaryInputs",
        doc="The boundary and the block edges: select the boundary's source together with "
        "the block edges' and apply the filter. Closed polylines are the outer boundary "
        "(the largest) and holes, open polylines are block edges.",
    ),
    _polyline_input(
        name="BlockEdges",
        label="Block Edges",
        port_index=1,
        multiple_input=True,
        clean_command="RemoveAllBlockEdges",
        optional=True,
        doc="More block edges: open polylines, each from the boundary, a hole or another "
        "edge to the boundary, a hole or another edge (several polylines per input and "
        "several inputs both work).",
    ),
    _polyline_input(
        name="AuxiliaryLines",
        label="Auxiliary Lines",
        port_index=2,
        multiple_input=True,
        clean_command="RemoveAllAuxiliaryLines",
        optional=True,
        doc="Optional auxiliary lines inside blocks: open polylines, each from a side of the "
        "block holding its middle point to the opposite side (several polylines per "
        "input and several inputs both work). Used by the pinn method: its networks "
        "move the blocks' grid lines onto them.",
    ),
    _field_input(3),
    names=[
        ("PINNStructuredMeshMultiBlock", "PINN Structured Mesh (Multi-Block)"),
        ("PINNMultiBlockMesh", "PINN Multi-Block Mesh"),
    ],
    summary="Multi-block structured grid of a domain cut into four-sided blocks.",
    doc="Structured quadrilateral grid of a 2D domain that is not four-sided (an L, a "
    "step, a body in a channel), cut into four-sided blocks by block edges you draw "
    "(SPEC 10). Inputs: closed polylines (the outer boundary and holes) and open "
    "polylines (block edges); every block needs four corners (points where its "
    "outline turns by 30 degrees or more). Opposite sides of a block get the same "
    "number of cells and a node on a shared side is the same point in both blocks. "
    "Output: one structured grid a block (block0, block1, ...) with the cells' "
    "MaxIncludedAngle, MinIncludedAngle, ScaledJacobian and Folded, and the report as "
    "field data. Guide: docs/multiblock.md of the pinn-mesh checkout. Blocking "
    "Automatic proposes the block edges from the boundary and its holes alone (SPEC 13, "
    "docs/blocking.md); the second output, Block Edges, holds the edges meshed, to copy, "
    "edit and connect as block edges.",
)
@smproperty.xml('<OutputPort name="Blocks" index="0"/>')
@smproperty.xml('<OutputPort name="Block Edges" index="1"/>')
@_field_array
@_panel("blocks")
class PINNStructuredMeshMultiBlock(PinnMultiBlockAlgorithm):
    """The ParaView face of
    :class:`pinn_engine.routes.multiblock_algorithm.PinnMultiBlockAlgorithm`."""

    def __init__(self):
        super().__init__()
        _watch_displays()

    def RemoveAllBoundaryInputs(self):
        # clean commands of the three repeatable inputs (_polyline_input)
        self.RemoveAllInputConnections(0)

    def RemoveAllBlockEdges(self):
        self.RemoveAllInputConnections(1)

    def RemoveAllAuxiliaryLines(self):
        self.RemoveAllInputConnections(2)


@_mesh_filter(
    _polyline_input(
        name="Input",
        port_index=0,
        doc="A closed triangulated surface whose six faces are tagged by a cell array FaceId "
        "(six values), e.g. a .vtp or .vtk file, or an untagged one such as an STL file, "
        "whose faces are found at its edges sharper than Face Angle; the faces must meet as "
        "a cube's do.",
    ),
    names=[
        ("PINNStructuredMeshHexahedral", "PINN Structured Mesh (Hexahedral)"),
        ("PINNHexahedralMesh", "PINN Hexahedral Mesh"),
    ],
    summary="Hexahedral structured grid of a six-faced 3D domain.",
    doc="Hexahedral structured grid (one block, ni x nj x nk nodes) of the 3D domain "
    "bounded by a closed surface with six faces, tagged by a FaceId cell array (SPEC 11) or "
    "found at Face Angle (an STL file): a duct, a bend, a nozzle, a box with a bump. The "
    "faces' 8 corners and 12 edges are found from their adjacency; each face gets a grid "
    "on the surface's triangles, and the volume grid is made from the six face grids by "
    "the chosen method. Corner 0 is "
    "the one with the smallest x + y + z, i leaves it nearest +x, and (i, j, k) is "
    "right-handed. Cells carry MaxIncludedAngle, MinIncludedAngle (the 24 face-corner "
    "angles), ScaledJacobian and Folded; field data the report and the patch names "
    "(Patch Names; default imin ... kmax). Guide: docs/hexa.md of the pinn-mesh checkout.",
)
@_panel("hexa")
class PINNStructuredMeshHexahedral(PinnHexaAlgorithm):
    """The ParaView face of :class:`pinn_engine.routes.hexa_algorithm.PinnHexaAlgorithm`."""

    def __init__(self):
        super().__init__()
        _watch_displays()


@smproxy.reader(
    name="PINNAirfoilReader",
    label="Airfoil Reader",
    extensions="dat",
    file_description="Airfoil coordinates (Selig or Lednicer)",
    support_reload=False,
)
@smproperty.xml(
    _proxy_doc(
        "An airfoil .dat file (Selig or Lednicer) as a polyline.",
        "Reads an airfoil .dat file (Selig or Lednicer coordinates) as one polyline, "
        "for PINN Structured Mesh with Topology O-grid or C-grid (docs/airfoils.md).",
    )
)
class PINNAirfoilReader(AirfoilReader):
    """An airfoil .dat file as a polyline, for PINN Structured Mesh with Topology O/C."""

    @smproperty.stringvector(name="FileName", panel_visibility="never")
    @smdomain.filelist()
    def SetFileName(self, name):
        AirfoilReader.SetFileName(self, name)


@smproxy.reader(
    name="PINNBlockMeshDictReader",
    label="PINN blockMeshDict Reader",
    filename_patterns="blockMeshDict*",
    file_description="OpenFOAM blockMeshDict (meshed by pinn-mesh)",
    support_reload=False,
)
@smproperty.xml(
    _proxy_doc(
        "An OpenFOAM blockMeshDict's blocks, meshed.",
        "Reads an OpenFOAM blockMeshDict and meshes its blocks with the dictionary's "
        "counts, gradings and patches: Method pinn (default) keeps the better of the 3D "
        "Winslow grid over all blocks and blockMesh's placement by checkMesh's largest "
        "non-orthogonality and skewness, elliptic the Winslow grid, tfi blockMesh's "
        "placement (docs/blockmesh.md).",
    )
)
@_panel("dictionary")
class PINNBlockMeshDictReader(PinnBlockMeshDictReader):
    """An OpenFOAM blockMeshDict's blocks as a multi-block dataset (SPEC 15)."""

    @smproperty.stringvector(name="FileName", panel_visibility="never")
    @smdomain.filelist()
    def SetFileName(self, name):
        PinnBlockMeshDictReader.SetFileName(self, name)


@smproxy.source(name="PINNAirfoilSource", label="Airfoil", support_reload=False)
@smhint.xml(_MENU)
@smproperty.xml(
    _proxy_doc(
        "A NACA 4-digit airfoil of chord 1 as a polyline.",
        "A NACA 4-digit section of chord 1 as one polyline (sharp trailing edge for "
        "the C-grid, the classical blunt one for the O-grid), for PINN Structured "
        "Mesh with Topology O-grid or C-grid (docs/airfoils.md).",
    )
)
@_panel("airfoil")
class PINNAirfoilSource(AirfoilSource):
    """A NACA 4-digit section of chord 1, for PINN Structured Mesh with Topology O/C."""


def _writer_proxy(key, extension, name, file_type):
    """File > Save Data entry for one solver format (``pinn_engine.io.export``)."""
    fmt = FORMATS[key]
    thickness = (
        "One cell of this thickness in z (0: the grid's mean edge length); "
        "OpenFOAM meshes are always 3D."
        if key == "openfoam"
        else "0 writes a 2D grid; a thickness T writes one cell of thickness T in z."
    )

    class Writer(GridWriter):
        FORMAT = key

        @smproperty.stringvector(name="FileName", panel_visibility="never")
        @smdomain.filelist()
        def SetFileName(self, name):
            GridWriter.SetFileName(self, name)

        if fmt.extrudes:
            # default 0: Save Data's writer dialog asks whether it has anything to show
            # before the information is read, and an empty IsThreeD hid Extrude Thickness
            @smproperty.intvector(
                name="IsThreeD", information_only="1", number_of_elements=1, default_values=0
            )
            def GetIsThreeD(self):
                return GridWriter.GetIsThreeD(self)

            @_doublevector(
                name="ExtrudeThickness",
                label="Extrude Thickness",
                default_values=0.0,
                bounds={"min": 0.0},
                hint=_TWO_D_INPUT,
                doc=thickness,
            )
            def SetExtrudeThickness(self, value):
                GridWriter.SetExtrudeThickness(self, value)

    Writer.__name__ = Writer.__qualname__ = name
    Writer.__module__ = __name__
    return _stack(
        smproxy.writer(
            name=name,
            label=name,
            extensions=extension,
            file_description=file_type,
            support_reload=False,
        ),
        smproperty.xml(
            _proxy_doc(
                f"Writes the grid as {fmt.description}.",
                f"Writes a grid of the PINN Structured Mesh filters (Multi-Block: its blocks) "
                f"as {fmt.description}, with the grid's Patch "
                "Names as boundary patches (docs/export.md).",
            )
        ),
        smproperty.input(name="Input", port_index=0),
        smdomain.datatype(dataTypes=["vtkStructuredGrid"], composite_data_supported=True),
    )(Writer)


_watch_displays()
_define_old_names()
if vtkSMProxyManager is not None:
    vtkSMProxyManager.GetProxyManager().AddObserver(
        vtkSMProxyManager.ActiveSessionChanged, _define_old_names
    )

for _key, (_extension, _name, _file_type) in PARAVIEW_FORMATS.items():
    globals()[_name] = _writer_proxy(_key, _extension, _name, _file_type)
# ParaView 5.11's Save Data creates the first writer (by proxy name) that takes the file's
# extension, whatever file type was chosen: its own CGNSWriter came before PINNMeshCGNSWriter.
# The same writer under a name that sorts first makes .cgns files of these grids ours (one
# entry in the list: the two share their file type).
_extension, _name, _file_type = PARAVIEW_FORMATS["cgns"]
globals()[CGNS_FIRST] = _writer_proxy("cgns", _extension, CGNS_FIRST, _file_type)
del (
    _key,
    _extension,
    _name,
    _file_type,
)  # one module name per proxy: ParaView registers every one it finds


def help_xmls():
    """The XML of the proxies with a help page: every one, the CGNS writer once, by the name
    Save Data creates (``CGNS_FIRST``)."""
    twin = PARAVIEW_FORMATS["cgns"][1]
    return get_plugin_xmls({k: v for k, v in globals().items() if k != twin})


# the proxies' help pages, for the panel's "?" and the help's search (docs/paraview_gui.md)
register_in_gui(help_xmls())
