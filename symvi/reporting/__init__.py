"""Scenes, their cache and the report: :mod:`.scenes` (the shipped scenes, what each
output computes and its cache key), :mod:`.report` (``symvi reproduce``) and
:mod:`.figures` (every plot).  The top of the layers below the CLI.  (Named
``reporting``: ``symvi.report`` was the old path of :mod:`.report`, a deprecated shim
for one release.)"""
