"""The codegen layer: loading the generated jets of the impact map, their one
input layout, and jets at a point or an orbit (:mod:`symvi.codegen.jets`)."""
