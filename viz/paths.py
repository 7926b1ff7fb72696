"""The fixed entity-path scheme and timelines of every wallsim recording.

World (2D or 3D scene, in metres)::

    world/particles        Points2D/3D: positions per frame; radii static; colours per frame
    world/blocks           LineStrips2D: outlines of polygon blocks (a block wall),
                           coloured by displacement since the first frame
    world/water            LineStrips2D: the water surface on the inner face of a block wall
    world/joint_forces     Points2D: contact points of the block joints, radius ~ normal force
    world/grains           LineStrips2D: outlines of polygonal grains (a fill behind a block
                           wall), held ones darker
    world/block_velocity   Arrows2D: block velocities (a block wall at failure)
    world/wall             LineStrips: wall panels, coloured by normal stress
    world/force_chains     LineStrips: contacts above the mean normal force, radius ~ force
    world/displacement     Arrows: particle displacement since the first frame (subsampled)
    world/sheet_pile       Points3D: the balls of a bonded sheet pile, coloured by the bending
                           moment of their row (blue negative, white 0, red positive)
    world/shear_strain     Boxes3D: the maximum shear strain per x-z cell (viridis), drawn
                           beside the periodic slab at its snapshot times

Wall pressure profile (a 2D plot: x = sigma_h / (gamma H), y = -depth / H)::

    profile/dem            LineStrips2D + Points2D of the DEM panel stresses, per frame
    profile/theory/<name>  LineStrips2D of each theory's sigma_h(z), static

Time series::

    metrics/K              load coefficient of the wall
    metrics/thrust_kN      normal thrust per metre of wall
    metrics/resultant_height_over_H       height of the resultant / H
    metrics/panel_stress_kPa/<i>   normal stress on panel i
    metrics/kinetic_energy_J
    metrics/crest_displacement_mm   outward crest movement of a block wall
    metrics/water_height_m          water height on its inner face
    metrics/backfill_height_m       fill height at its inner face
    metrics/thrust_kN               also the fill's horizontal thrust on a block wall

    case                   TextDocument: case description and resolved config (static)

Timelines: ``step`` (sequence), ``sim_time`` (duration, s) and, for wall-movement runs,
``wall_disp_over_H`` (sequence in millionths: Delta/H = 0.003 is 3000), because Rerun
timelines are integers or times.
"""

WORLD = "world"
PARTICLES = "world/particles"
BLOCKS = "world/blocks"
WATER = "world/water"
JOINT_FORCES = "world/joint_forces"
GRAINS = "world/grains"
BLOCK_VELOCITY = "world/block_velocity"
WALL = "world/wall"
FORCE_CHAINS = "world/force_chains"
DISPLACEMENT = "world/displacement"
SHEET_PILE = "world/sheet_pile"
SHEAR_STRAIN = "world/shear_strain"
PROFILE = "profile"
PROFILE_DEM = "profile/dem"
PROFILE_THEORY = "profile/theory"
METRICS = "metrics"
METRIC_K = "metrics/K"
METRIC_THRUST = "metrics/thrust_kN"
METRIC_RESULTANT_HEIGHT = "metrics/resultant_height_over_H"
METRIC_PANEL_STRESS = "metrics/panel_stress_kPa"
METRIC_KE = "metrics/kinetic_energy_J"
CASE = "case"

TIMELINE_STEP = "step"
TIMELINE_TIME = "sim_time"
TIMELINE_DISP = "wall_disp_over_H"
DISP_TIMELINE_SCALE = 1e6
