"""Independent checks of the chain: the 50-digit validation chains A and B
(:mod:`.mpcheck`), the 50-digit check of codimension-two points (:mod:`.codim2_check`)
and the invariant circle against the normal form (:mod:`.circle_check`)."""
