"""The element tests of the granular materials, in one place over the engines: the 3D
cubical triaxial cell (``triaxial``: six servo platens, sigma_2 = sigma_3), the 2D
biaxial test with a stress-controlled piston and its band angle (``biaxial``; with
gravel grains, ``gravel_biaxial``), and the constant-normal-load interface shear of
gravel over a block face (``interface``). The calibrations (``calibrate triaxial``,
``biaxial``, ``gravel``) and the studies that need a material's angle run them."""
