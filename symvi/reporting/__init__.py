"""Scenes, their cache and the report: :mod:`.scenes` (the shipped scenes, what each
output computes and its cache key), :mod:`.report` (``symvi reproduce``) and
:mod:`.figures` (every plot).  The top of the layers below the CLI.  (Named
``reporting`` because ``symvi.report`` stays the module it always was.)"""
