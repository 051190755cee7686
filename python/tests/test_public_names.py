"""Every name a user of the package could hold stays where it was: the names of
``stillpoint`` before its split into modules by concern, written out here, are all still
attributes of the package, and the public functions and classes say they are
``stillpoint``'s (pickles and ``help`` name the path users import)."""

import pickle

import stillpoint as sp

# `__all__`, `__version__` and the extension module that the benches and tests reach
# (`stillpoint._core.randomize`, `.tent_set`), as stillpoint 0.1.0 had them.
BEFORE = set(
    """Design Engine baseline baselines design design_figures discrepancy extend generate
    generate_many integrate metrics nested __version__ _core""".split()
)


def test_every_public_name_of_before_is_still_there():
    assert BEFORE <= set(dir(sp))
    assert {n for n in BEFORE if not n.startswith("_")} <= set(sp.__all__)


def test_no_submodule_shadows_a_public_name():
    # A module named like a function (stillpoint/generate.py) would be what
    # `import stillpoint.generate` gives; the modules by concern are private.
    for name in sp.__all__:
        assert not isinstance(getattr(sp, name), type(sp)), name


def test_public_names_are_the_packages_own():
    for name in sp.__all__:
        value = getattr(sp, name)
        assert value.__module__ == "stillpoint", name
        assert pickle.loads(pickle.dumps(value)) is value
