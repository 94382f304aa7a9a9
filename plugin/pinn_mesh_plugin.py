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

Property order: ParaView 5.11 lists a Python plugin's properties alphabetically by method
name, so the methods below carry a numeric prefix (``P01...``) that keeps the panel in the
intended order in every version. Each property and input is one call of a helper
(``_intvector``, ``_polyline_input``, ...) that applies ParaView's decorator stack in its fixed
order (``_stack``), so the plugin's XML is what the stacks written out would give.
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
    from pinn_engine.routes.multiblock_algorithm import (
        BLOCKING,
        INTERFACES,
        PinnMultiBlockAlgorithm,
    )
    from pinn_engine.routes.paraview_help import register_in_gui
    from pinn_engine.settings import (
        ADAPT_STRENGTH,
        BLOCKS_METHOD,
        FACE_ANGLE,
        HEXA_METHOD,
        HEXA_METHODS,
        HEXA_SIZE,
        MAX_SIDE_NODES,
        METHODS,
        MIN_HEXA_NODES,
        MULTIBLOCK_METHODS,
        OBJECTIVES,
        PANEL_TIME_LIMIT,
        PARAMETER_CONSTRAINTS,
        PRESETS,
        Settings,
        make_settings,
    )
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

_DEFAULTS = Settings()
_COLOUR_ARRAY = "MaxIncludedAngle"  # what a new grid is coloured by
_MESH_FILTERS = set()  # whose displays get that colour: the proxy names _mesh_filter made
_OLD_NAMES = []  # (old proxy name, its definition): the filters' old names (_mesh_filter)
_MENU = '<ShowInMenu category="Mesh Generation"/>'  # where the filters and the Airfoil source are
_OBSERVERS = []  # the display observers (_ColourWhenDataArrives)
# id(session proxy manager): (it, its RegisterEvent observer, the observer's id); VTK's own
# reference to a Python observer was not enough in the GUI (a closure crashed on its 2nd call)
_WATCHED_SESSIONS = {}
_NEURAL = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="Method" values="0 1"/>'
)  # training settings: pinn and mgnet only
_FOUR_SIDED = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="Topology" values="0 3"/>'
)  # SPEC 7 settings: four-sided domains (and Automatic, which may pick one)
_BODY = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="Topology" values="1 2 3"/>'
)  # O- and C-grid settings (and Automatic, which may pick an O-grid)


def _for_preset(preset, methods):
    """Shown only under Preset ``preset`` (index) and for the Method indices ``methods``."""
    return (
        '<PropertyWidgetDecorator type="CompositeDecorator"><Expression type="and">'
        '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        f'property="Method" values="{methods}"/>'
        '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        f'property="Preset" value="{preset}"/>'
        "</Expression></PropertyWidgetDecorator>"
    )


_PAPER = make_settings("pinn", "paper")
_TWO_D_INPUT = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="IsThreeD" value="0"/>'
)  # writer settings that only a 2D grid has (a hexahedral grid is not extruded)
CGNS_FIRST = "CGNSPINNMeshWriter"  # sorts before ParaView's CGNSWriter (see the writers below)
_TIME_LIMIT_DOC = (
    "Seconds of training, then the grid of the best state so far is produced with a warning "
    "(0: no limit). ParaView 5.11 handles no event while a filter runs, so its progress "
    "bar's abort cannot stop a training: set this before Apply (or stop it with "
    "pkill -USR1 -x paraview, which also keeps the best grid so far)."
)


def _method_is(methods, name):
    """Shown only while Method is ``name`` (of ``methods``, the panel's enumeration)."""
    return (
        '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        f'property="Method" value="{methods.index(name)}"/>'
    )


_PINN_ONLY = (
    '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
    'property="Method" value="0"/>'
)


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


def _range(name):
    """The panel range of a whole-number setting, from settings.PARAMETER_CONSTRAINTS."""
    rule = PARAMETER_CONSTRAINTS[name]
    return {"min": int(rule.low), "max": int(rule.high)}


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
            '<InputArrayDomain name="field_arrays" attribute_type="any" optional="1"/>'
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


def _adapt_properties(cls):
    """Field Array and Adapt Strength on a 2D filter's panel, after its other properties."""

    @smproperty.xml(_FIELD_ARRAY)
    def P90FieldArray(self, *selection):
        self.SetAdaptArray(*selection)

    @_doublevector(
        name="AdaptStrength",
        label="Adapt Strength",
        default_values=ADAPT_STRENGTH,
        bounds={"min": 0.0, "max": 100.0},
        doc="With a Field input: the monitor's strength beta, M = sqrt(1 + beta^2 |grad f|^2 "
        "/ max |grad f|^2); cells where M is large get smaller. The grid is adapted less "
        "where the worst cell would exceed the unadapted one's by more than 10 degrees, "
        "and kept unadapted where that carries the field no better.",
    )
    def P91AdaptStrength(self, beta):
        self.SetAdaptStrength(float(beta))

    cls.P90FieldArray, cls.P91AdaptStrength = P90FieldArray, P91AdaptStrength
    return cls


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
@_adapt_properties
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

    @_intvector(
        name="Method",
        default_values=0,
        enum=METHODS,
        doc="pinn: the paper's PINN (uses the auxiliary lines); mgnet: plain "
        "networks, no auxiliary lines; tfi: transfinite interpolation; "
        "elliptic: the classical elliptic (Winslow) method.",
    )
    def P01Method(self, index):
        self.SetMethod(int(index))

    @_intvector(
        name="GridSize",
        label="Grid Size",
        default_values=[41, 21],
        bounds={"min": 2, "max": MAX_SIDE_NODES},
        doc="Nodes along xi and eta. The default PINN starts from the elliptic "
        "grid of this size and trains anew for a new size (seconds); with "
        "Preset paper a new size re-evaluates the trained network.",
    )
    def P02GridSize(self, ni, nj):
        self.SetGridSize(ni, nj)

    @_intvector(
        name="Preset",
        default_values=0,
        enum=PRESETS,
        doc="default: measured defaults (exact boundary, arc-length fit); paper: "
        "the paper's section 4 (penalty boundary term, decision-tree fit, "
        "1000 elliptic sweeps). Adam Epochs, L-BFGS Iterations and Lambda2 "
        "have a field per preset; the panel shows the chosen preset's.",
    )
    def P03Preset(self, index):
        self.SetPreset(int(index))

    @_doublevector(
        name="TimeLimit",
        label="Time Limit",
        default_values=PANEL_TIME_LIMIT,
        bounds={"min": 0.0},
        hint=_NEURAL,
        doc="Seconds of training, then the grid of the best state so far is produced with a "
        "warning (0: no limit). ParaView handles no event while a filter runs; "
        "pkill -USR1 -x paraview ends a training early the same way.",
    )
    def P03TimeLimit(self, seconds):
        self.SetPanelSetting("time_limit", float(seconds))

    @_intvector(
        name="AdamEpochs",
        label="Adam Epochs",
        default_values=_DEFAULTS.adam_epochs,
        panel_visibility="advanced",
        bounds=_range("adam_epochs"),
        hint=_for_preset(0, "0 1"),
        doc="Adam epochs of training under Preset default.",
    )
    def P04AdamEpochs(self, n):
        self.SetPresetSetting("default", "adam_epochs", int(n))

    @_intvector(
        name="PaperAdamEpochs",
        label="Paper Adam Epochs",
        default_values=_PAPER.adam_epochs,
        panel_visibility="advanced",
        bounds=_range("adam_epochs"),
        hint=_for_preset(1, "0 1"),
        doc="Adam epochs of training under Preset paper (the paper's 5000).",
    )
    def P04PaperAdamEpochs(self, n):
        self.SetPresetSetting("paper", "adam_epochs", int(n))

    @_intvector(
        name="LBFGSIterations",
        label="L-BFGS Iterations",
        default_values=_DEFAULTS.lbfgs_iterations,
        panel_visibility="advanced",
        bounds=_range("lbfgs_iterations"),
        hint=_for_preset(0, "0 1"),
        doc="L-BFGS iterations after Adam under Preset default.",
    )
    def P05LBFGSIterations(self, n):
        self.SetPresetSetting("default", "lbfgs_iterations", int(n))

    @_intvector(
        name="PaperLBFGSIterations",
        label="Paper L-BFGS Iterations",
        default_values=_PAPER.lbfgs_iterations,
        panel_visibility="advanced",
        bounds=_range("lbfgs_iterations"),
        hint=_for_preset(1, "0 1"),
        doc="L-BFGS iterations after Adam under Preset paper (the paper's 500).",
    )
    def P05PaperLBFGSIterations(self, n):
        self.SetPresetSetting("paper", "lbfgs_iterations", int(n))

    @_intvector(
        name="HiddenLayers",
        label="Hidden Layers",
        default_values=_DEFAULTS.hidden_layers,
        panel_visibility="advanced",
        bounds=_range("hidden_layers"),
        hint=_NEURAL,
        doc="Hidden layers of each sub-network.",
    )
    def P06HiddenLayers(self, n):
        self.SetPanelSetting("hidden_layers", int(n))

    @_intvector(
        name="Neurons",
        default_values=_DEFAULTS.neurons,
        panel_visibility="advanced",
        bounds=_range("neurons"),
        hint=_NEURAL,
        doc="Neurons per hidden layer.",
    )
    def P07Neurons(self, n):
        self.SetPanelSetting("neurons", int(n))

    @_doublevector(
        name="Lambda2",
        default_values=_DEFAULTS.lambda2,
        bounds={"min": 0.0, "max": 1000.0},
        hint=_for_preset(0, "0"),
        doc="Weight of the auxiliary-line term of the loss under Preset default.",
    )
    def P08Lambda2(self, value):
        self.SetPresetSetting("default", "lambda2", float(value))

    @_doublevector(
        name="PaperLambda2",
        label="Paper Lambda2",
        default_values=_PAPER.lambda2,
        bounds={"min": 0.0, "max": 1000.0},
        hint=_for_preset(1, "0"),
        doc="Weight of the auxiliary-line term under Preset paper (the paper's 10).",
    )
    def P08PaperLambda2(self, value):
        self.SetPresetSetting("paper", "lambda2", float(value))

    @_intvector(
        name="Seed",
        default_values=_DEFAULTS.seed,
        panel_visibility="advanced",
        hint=_NEURAL,
        doc="Random seed of training (runs are repeatable).",
    )
    def P09Seed(self, n):
        self.SetPanelSetting("seed", int(n))

    @_intvector(
        name="CornerIndices",
        label="Corner Indices",
        default_values=[-1, -1, -1, -1],
        doc="The four corner point indices of the boundary; -1 -1 -1 -1 finds "
        "them automatically (the four sharpest turns).",
    )
    def P10CornerIndices(self, i0, i1, i2, i3):
        self.SetCorners(i0, i1, i2, i3)

    @_intvector(
        name="Objective",
        default_values=OBJECTIVES.index(_DEFAULTS.objective),
        enum=OBJECTIVES,
        hint=_PINN_ONLY,
        doc="best (default): the grid of lowest worst cell among TFI, the elliptic grid, "
        "their blends and the quality-optimised grid, its mean at most 0.5 degrees above "
        "the elliptic grid's, auxiliary lines followed (winslow under a spacing or "
        "orthogonal sides); winslow: train on the Winslow equations; quality: add a "
        "cell-quality term that lowers the worst cell's largest angle, starting from the "
        "better of the elliptic and TFI grids (pinn only).",
    )
    def P11Objective(self, index):
        self.SetPanelSetting("objective", OBJECTIVES[int(index)])

    @_intvector(
        name="Topology",
        default_values=3,
        inline_domain=_enum(("Four-sided domain", "O-grid", "C-grid", "Automatic")),
        doc="Automatic (default): an O-grid for a body (the Airfoil source or reader's "
        "curve, one curve that turns sharply at two points at most, or two closed "
        "polylines: body inside far field), else a four-sided domain. "
        "Four-sided domain: the input is a closed boundary with four corners. O-grid / "
        "C-grid: the input is a body such as an airfoil (the Airfoil source, or a .dat file "
        "opened with the Airfoil reader): one curve, meshed out to a far-field circle of Far "
        "Field Radius chords, or two closed polylines (body inside far field). The C-grid's "
        "wake cut leaves a sharp trailing edge, or a blunt base's middle. Methods pinn, tfi, "
        "elliptic (docs/airfoils.md).",
    )
    def P11Topology(self, index):
        self.SetTopology(int(index))

    @_doublevector(
        name="FarFieldRadius",
        label="Far Field Radius",
        default_values=15.0,
        bounds={"min": 1.0},
        hint=_BODY,
        doc="Far-field circle radius in chords about mid-chord.",
    )
    def P12FarFieldRadius(self, radius):
        self.SetFarFieldRadius(radius)

    @_doublevector(
        name="WallSpacing",
        label="Wall Spacing",
        default_values=0.0,
        bounds={"min": 0.0},
        hint=_BODY,
        doc="First-layer height off the body wall, in the body's units (0: half "
        "the mean node spacing along the wall).",
    )
    def P13WallSpacing(self, h):
        self.SetWallSpacing(h)

    @_doublevector(
        name="FirstEdgeSpacing",
        label="First Edge Spacing",
        default_values=[0.0, 0.0, 0.0, 0.0],
        hint=_FOUR_SIDED,
        doc="Length of the first grid edge leaving the bottom, right, top and "
        "left sides, in the boundary's units (0: that side keeps the even "
        "distribution). The spacing grows smoothly away from the side "
        "(Vinokur's stretching); pinn, tfi and elliptic, four-sided domains "
        "(docs/boundary_layer.md).",
    )
    def P14FirstEdgeSpacing(self, bottom, right, top, left):
        self.SetSpacing(float(bottom), float(right), float(top), float(left))

    @_intvector(
        name="OrthogonalSides",
        label="Orthogonal Sides",
        default_values=[0, 0, 0, 0],
        bounds={"min": 0, "max": 1},
        hint=_FOUR_SIDED,
        doc="1 for each of the bottom, right, top and left sides that grid lines "
        "are to leave at 90 degrees (pinn: a loss term; elliptic: "
        "Hilgenstock control functions; not tfi or mgnet).",
    )
    def P15OrthogonalSides(self, bottom, right, top, left):
        self.SetOrthogonal(int(bottom), int(right), int(top), int(left))

    @_stringvector(
        name="PatchNames",
        label="Patch Names",
        default_values="bottom right top left",
        doc="Boundary patch names for solver formats (File > Save Data: PLOT3D, "
        "CGNS, SU2, Gmsh, OpenFOAM): four names for the bottom, right, top "
        "and left sides, or SIDE=NAME items such as 'bottom=wall top=wall'. "
        "Sides with the same name form one patch.",
    )
    def P20PatchNames(self, text):
        self.SetPatchNames(text)

    @_stack(
        smproperty.stringvector(name="Model", label="Model", default_values=""),
        smdomain.filelist(),
        smhint.filechooser(extensions="pt", file_description="pinn-mesh family models"),
        smdomain.xml(
            _doc(
                "A family model (a .pt file made by pinn-mesh fit, docs/family.md): the "
                "boundary is meshed as a member of its family, its interior in a forward "
                "pass instead of its own run, and its Grid Size must be the family's. "
                "Empty: no model."
            )
        ),
    )
    def P21Model(self, path):
        self.SetModel(path or None)


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
@_adapt_properties
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

    @_intvector(
        name="Blocking",
        default_values=0,
        enum=[b.capitalize() for b in BLOCKING],
        doc="Manual: the block edges are the open polylines you give (on Input or Block "
        "Edges); with none given, they are proposed as by Automatic. Automatic: they are "
        "proposed from the boundary and its holes alone (leave Block Edges empty): O-rings "
        "round holes, an edge from each concave corner, junction centres cut round their "
        "middle (docs/blocking.md); the output port Block Edges shows them.",
    )
    def P00Blocking(self, index):
        self.SetBlocking(int(index))

    @_intvector(
        name="Method",
        default_values=MULTIBLOCK_METHODS.index(BLOCKS_METHOD),
        enum=MULTIBLOCK_METHODS,
        doc="pinn (default): each block's network trained on the Winslow equations from "
        "the elliptic grid of all blocks, its sides held, kept where it is no worse (and "
        "fitted to auxiliary lines, if given; Time Limit bounds the training); elliptic: "
        "Winslow on all blocks at once (interface nodes move like interior nodes); tfi: "
        "each block's transfinite interpolation of its side nodes.",
    )
    def P01Method(self, index):
        self.SetMethod(int(index))

    @_doublevector(
        name="TimeLimit",
        label="Time Limit",
        default_values=PANEL_TIME_LIMIT,
        bounds={"min": 0.0},
        hint=_method_is(MULTIBLOCK_METHODS, "pinn"),
        doc=_TIME_LIMIT_DOC,
    )
    def P01TimeLimit(self, seconds):
        self.SetTimeLimit(float(seconds))

    @_doublevector(
        name="CellSize",
        label="Cell Size",
        default_values=0.0,
        bounds={"min": PARAMETER_CONSTRAINTS["cell_size"].low},
        doc="Cell length in the boundary's units (0: the domain's diagonal / 40). A chain "
        "of opposite sides through the blocks takes its longest side over the cell "
        "size, rounded up, at least 2 cells.",
    )
    def P02CellSize(self, h):
        self.SetCellSize(h)

    @_intvector(
        name="Interfaces",
        default_values=0,
        enum=INTERFACES,
        doc="free: interface nodes are solved like interior nodes, so grid lines cross "
        "the block edges smoothly (elliptic); fixed: they stay on the drawn edges.",
    )
    def P03Interfaces(self, index):
        self.SetInterfaces(int(index))

    @_stringvector(
        name="PatchNames",
        label="Patch Names",
        default_values="",
        doc="Names of boundary pieces (a piece runs between two block corners or "
        "junctions), for solver formats and for First Edge Spacing and Orthogonal "
        "Patches: items separated by spaces, X,Y=NAME[:TYPE] naming the piece nearest "
        "(X, Y) (negative coordinates too), hole1=NAME[:TYPE] or boundary=NAME[:TYPE] "
        "every piece of that ring, e.g. 'hole1=cylinder:wall -0.5,0=inlet:inflow'. "
        "Pieces with the same name form one patch; unnamed pieces are boundary, hole1, "
        "hole2, ...",
    )
    def P04PatchNames(self, text):
        self.SetPatchNames(text)

    @_stringvector(
        name="FirstEdgeSpacing",
        label="First Edge Spacing",
        default_values="",
        doc="Length of the first grid edge leaving a patch, in the boundary's units: "
        "NAME=H items separated by spaces, e.g. 'cylinder=0.005' (empty: none); X,Y=H "
        "items grade the blocks across the block side nearest (X, Y), interior ones "
        "too: the cells on both sides H across it, growing along the chain by at most "
        "1.25 a cell, e.g. '0.3,0.2=0.005'. The spacing grows smoothly away from the "
        "patch (Vinokur's stretching); all methods (docs/multiblock.md).",
    )
    def P05FirstEdgeSpacing(self, text):
        self.SetSpacing(text)

    @_stringvector(
        name="OrthogonalPatches",
        label="Orthogonal Patches",
        default_values="",
        doc="Patches that grid lines leave at 90 degrees: names separated by commas, "
        "e.g. 'cylinder' (empty: none); all methods.",
    )
    def P06OrthogonalPatches(self, text):
        self.SetOrthogonal(text)

    @_stringvector(
        name="CellCounts",
        label="Cell Counts",
        default_values="",
        doc="Cells along chosen chains of block sides: X,Y=N items separated by spaces, "
        "each giving the chain through the block side nearest (X, Y) N cells, e.g. "
        "'1.2,0.41=60' (empty: every chain from Cell Size). Opposite sides of every "
        "block share a count.",
    )
    def P07CellCounts(self, text):
        self.SetCells(text)

    @_stringvector(
        name="Gradings",
        label="Gradings",
        default_values="",
        doc="Expansion ratios along chosen chains of block sides, as blockMesh grades: "
        "X,Y=R items separated by spaces, each growing the cells along the chain through "
        "the block side nearest (X, Y) geometrically, the last R times the first (the first "
        "at that side's end nearest the point), e.g. '1.5,-2=4' (empty: none).",
    )
    def P08Gradings(self, text):
        self.SetGradings(text)


_HEXA_METHOD_DOCS = {
    "tfi": "3D transfinite interpolation of the six face grids",
    "elliptic": "the 3D Winslow equations solved to convergence from the TFI grid",
    "pinn": "a physics-informed network trained on the 3D Winslow equations, the face "
    "grids built in",
}  # the Method help of PINN Structured Mesh (Hexahedral), for the methods settings.HEXA_METHODS has


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
class PINNStructuredMeshHexahedral(PinnHexaAlgorithm):
    """The ParaView face of :class:`pinn_engine.routes.hexa_algorithm.PinnHexaAlgorithm`."""

    def __init__(self):
        super().__init__()
        _watch_displays()

    @_intvector(
        name="Method",
        default_values=HEXA_METHODS.index(HEXA_METHOD),
        enum=HEXA_METHODS,
        doc="; ".join(f"{m}: {_HEXA_METHOD_DOCS[m]}" for m in HEXA_METHODS) + ".",
    )
    def P01Method(self, index):
        self.SetMethod(int(index))

    @_intvector(
        name="GridSize",
        label="Grid Size",
        default_values=list(HEXA_SIZE),
        bounds={"min": MIN_HEXA_NODES},
        doc="Nodes along i, j and k (at least 3 each).",
    )
    def P02GridSize(self, ni, nj, nk):
        self.SetGridSize(ni, nj, nk)

    @_doublevector(
        name="TimeLimit",
        label="Time Limit",
        default_values=PANEL_TIME_LIMIT,
        bounds={"min": 0.0},
        hint=_method_is(HEXA_METHODS, "pinn"),
        doc=_TIME_LIMIT_DOC,
    )
    def P02TimeLimit(self, seconds):
        self.SetTimeLimit(float(seconds))

    @_doublevector(
        name="FaceAngle",
        label="Face Angle",
        default_values=FACE_ANGLE,
        bounds={"min": 1.0, "max": 179.0},
        doc="For a surface without a FaceId cell array (an STL file): its faces are the "
        "regions between edges where neighbouring triangles' normals differ by more than "
        "this many degrees; there must be six. Ignored when the input has FaceId.",
    )
    def P03FaceAngle(self, degrees):
        self.SetFaceAngle(float(degrees))

    @_stringvector(
        name="PatchNames",
        label="Patch Names",
        default_values="",
        doc="Boundary patch names of the six faces for solver formats (File > Save Data: "
        "PLOT3D, CGNS, SU2, Gmsh, OpenFOAM): six names for imin, imax, jmin, jmax, kmin "
        "and kmax, or SIDE=NAME[:TYPE] items, SIDE one of those or faceN (the input face "
        "whose FaceId is N; Output Messages lists which side each face became), such as "
        "'face2=inlet:inflow kmin=floor:wall' (empty: the faces' own names). Faces with "
        "the same name form one patch.",
    )
    def P03PatchNames(self, text):
        self.SetPatchNames(text)

    @_stringvector(
        name="FirstEdgeSpacing",
        label="First Edge Spacing",
        default_values="",
        doc="Length of the first grid edge leaving a face, in the surface's units: PATCH=H "
        "items separated by spaces, PATCH one of imin, imax, jmin, jmax, kmin, kmax, "
        "e.g. 'kmin=0.002' (empty: none). The spacing grows smoothly away from the face; "
        "all methods (docs/hexa.md).",
    )
    def P04FirstEdgeSpacing(self, text):
        self.SetSpacing(text)

    @_stringvector(
        name="OrthogonalPatches",
        label="Orthogonal Patches",
        default_values="",
        doc="Faces that grid lines leave at 90 degrees: imin, imax, jmin, jmax, kmin or kmax "
        "separated by commas, e.g. 'kmin' (empty: none); elliptic and pinn.",
    )
    def P05OrthogonalPatches(self, text):
        self.SetOrthogonal(text)


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
class PINNBlockMeshDictReader(PinnBlockMeshDictReader):
    """An OpenFOAM blockMeshDict's blocks as a multi-block dataset (SPEC 15)."""

    @smproperty.stringvector(name="FileName", panel_visibility="never")
    @smdomain.filelist()
    def SetFileName(self, name):
        PinnBlockMeshDictReader.SetFileName(self, name)

    @smproperty.xml(
        """<IntVectorProperty name="Method" command="SetMethod" number_of_elements="1"
        default_values="0"><EnumerationDomain name="enum">
        <Entry value="0" text="pinn"/><Entry value="1" text="elliptic"/>
        <Entry value="2" text="tfi"/></EnumerationDomain><Documentation>pinn: the better
        of the Winslow grid and blockMesh's placement; elliptic: the 3D Winslow grid over
        all blocks; tfi: blockMesh's placement.</Documentation></IntVectorProperty>"""
    )
    def SetMethod(self, method):
        PinnBlockMeshDictReader.SetMethod(self, method)

    @smproperty.xml(
        """<IntVectorProperty name="Interfaces" command="SetInterfaces"
        number_of_elements="1" default_values="0"><EnumerationDomain name="enum">
        <Entry value="0" text="free"/><Entry value="1" text="fixed"/></EnumerationDomain>
        <Documentation>free: nodes on faces between blocks solved like interior nodes;
        fixed: blockMesh's placement of those faces kept.</Documentation>
        </IntVectorProperty>"""
    )
    def SetInterfaces(self, interfaces):
        PinnBlockMeshDictReader.SetInterfaces(self, interfaces)


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
class PINNAirfoilSource(AirfoilSource):
    """A NACA 4-digit section of chord 1, for PINN Structured Mesh with Topology O/C."""

    @_stringvector(
        name="NACA", label="NACA", default_values="0012", doc="Four digits, e.g. 0012 or 2412."
    )
    def P01NACA(self, code):
        self.SetNACA(code)

    @_intvector(
        name="SharpTrailingEdge",
        label="Sharp Trailing Edge",
        default_values=1,
        inline_domain='<BooleanDomain name="bool"/>',
        doc="Closed trailing edge (for the C-grid); off: the classical blunt one (O-grid).",
    )
    def P02SharpTrailingEdge(self, sharp):
        self.SetSharpTrailingEdge(sharp)


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
