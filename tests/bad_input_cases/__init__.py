"""One bad-input table per subpackage of amdo_lab (module ``bad_input_cases.<subpackage>``).

Each module defines ``cases()`` (public name -> :class:`bad_input_cases._core.Case`), ``EXEMPT``
(public name -> why it is not spoiled) and ``KNOWN_FAILURES`` ((name, argument, label) -> reason).
"""
