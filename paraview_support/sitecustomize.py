"""Compatibility shim for Debian 12's ParaView 5.11 on Python 3.11.

ParaView 5.11's ``paraview.detail.pythonalgorithm`` (imported whenever a
Python plugin is loaded) does ``from inspect import getargspec``, which was
removed in Python 3.11.  Without this shim every Python plugin fails with
``ImportError: cannot import name 'getargspec' from 'inspect'``.

Python imports ``sitecustomize`` automatically at start-up when it is on
``sys.path``; ``scripts/pvenv.sh`` puts this folder first on PYTHONPATH for
pvpython, pvbatch and the paraview GUI.

Do NOT place this file in a folder listed in PV_PLUGIN_PATH: ParaView tries
to load every ``.py`` file there as a plugin.
"""

import inspect

if not hasattr(inspect, "getargspec"):
    # getfullargspec returns a superset (args, varargs, varkw, defaults, ...);
    # pythonalgorithm only reads .args / .defaults, which keep their meaning.
    inspect.getargspec = inspect.getfullargspec
