"""Sphinx configuration of the AMDO Lab book (``python -m amdo_lab site`` runs sphinx-build with it).

The source folder is staged by ``amdo_lab.course.book.build_site``: the generated landing page
``index.md`` and the executed chapter notebooks. Notebooks are rendered as they are (never
executed here). Everything a page loads ships with the site: MathJax 3 comes from the
``sphinx-mathjax-offline`` package, the theme's fonts and icons from ``pydata-sphinx-theme``.
"""

project = "AMDO Lab"
author = "AMDO Lab authors"
copyright = "AMDO Lab authors"
html_title = "AMDO Lab"

extensions = [
    "myst_nb",                 # notebooks and MyST markdown
    "sphinx_copybutton",       # a copy button on code cells
    "sphinx_togglebutton",     # collapsible admonitions ({dropdown} / :class: dropdown)
    "sphinx-mathjax-offline",  # copies MathJax 3 into _static/mathjax (no CDN)
]

root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store"]

# --- notebooks: rendered from their committed / freshly executed outputs ---------------------
nb_execution_mode = "off"
nb_ipywidgets_js = {}          # no widget scripts from a CDN
nb_merge_streams = True        # one block per cell for consecutive prints
nb_render_markdown_format = "myst"  # Markdown outputs (chapter 0's reading map) with tables and math
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_dmath_double_inline = True  # $$...$$ on a line of its own inside a paragraph
myst_heading_anchors = 3

# --- equations: numbered, typeset by the local MathJax ----------------------------------------
numfig = True
math_numfig = True
math_eqref_format = "({number})"
mathjax_path = "mathjax/tex-chtml.js"  # relative to _static/, where the extension puts MathJax

# --- HTML ----------------------------------------------------------------------------------
html_theme = "sphinx_book_theme"
html_theme_options = {
    "use_download_button": True,      # download the .ipynb of a chapter
    "use_fullscreen_button": True,
    "use_repository_button": False,
    "home_page_in_toc": True,
    "show_toc_level": 2,
    "show_navbar_depth": 1,
    "navigation_with_keys": False,
}
html_sourcelink_suffix = ""           # _sources/<chapter>.ipynb keeps its own extension
html_last_updated_fmt = None
html_show_sphinx = False
html_permalinks_icon = "#"
html_static_path = ["_static"]
html_favicon = "_static/favicon.svg"  # also keeps browsers from asking for /favicon.ico
html_context = {"default_mode": "auto"}  # light or dark as the reader's system prefers
