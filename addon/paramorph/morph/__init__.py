"""Morph To and its pins (thesis ch. 4): the operators (`operators`: Preview
Matches, Add Pin, Morph To and the pair list's edits; `pins`: the Pick Pins
viewport tool), the scene's pins and pairs they share with the overlay
(`pin_store`), the morph's work off the main thread (`job`: numpy and
paramorph_native only) and the shape-keyed object it ends in
(`result_object`). Nothing is imported here, so the overlay can import
pin_store without the operators."""
