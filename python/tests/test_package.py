"""The package itself: submodules, the error class, docstrings with units."""

import pydoc

import atmosh


def test_error_class_and_submodules():
    assert issubclass(atmosh.InputError, ValueError)
    for name in ("sun", "atmo", "sky", "sh", "prt"):
        assert hasattr(atmosh, name)


def test_help_states_arguments_and_units():
    text = pydoc.render_doc(atmosh.sky.radiance, renderer=pydoc.plaintext)
    for word in ("views", "sun", "altitude_m", "W m^-2 sr^-1 nm^-1", "(N, wavelengths)"):
        assert word in text, word
    text = pydoc.render_doc(atmosh.sun.position, renderer=pydoc.plaintext)
    for word in ("latitude", "[deg]", "[hPa]", "equation_of_time_min"):
        assert word in text, word
