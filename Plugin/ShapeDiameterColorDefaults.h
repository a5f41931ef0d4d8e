// SPDX-License-Identifier: BSD-3-Clause
// Default colour maps for the plugin's label arrays, installed when ParaView loads the plugin.
#pragma once

/**
 * Registers array-specific colour-map defaults with ParaView's settings, so that
 * colouring by a part label gives a categorical lookup table without any user step:
 *
 * - `SDFCluster` and `SDFLevel1` ... `SDFLevel15` (vtkSDFGMMPartition): "Interpret
 *   Values As Categories" on, values 0-15 annotated "cluster N", 16 colours of high
 *   mutual contrast (Kelly's maximum-contrast sequence without white, black and grey,
 *   ordered so the first few are the most distinct), legend limited to the values
 *   present ("Show Categorical Colors in Data Range Only"), grey NaN colour.
 *
 * ParaView applies `array_lookup_tables.<array>.PVLookupTable.*` settings whenever it
 * creates the colour map of an array with that name (GUI, pvpython, pvbatch). The
 * collection is added at priority 0.5: above ParaView's built-in defaults (0), below
 * site settings (1) and the user's own settings, so "Save as default" for these arrays
 * still wins.
 *
 * Label arrays that may hold more than 32 values (`SDFSegment`, `BoneId`,
 * `SkeletonBoneId`) keep ParaView's continuous default: ParaView's categorical mode
 * finds the values present by sampling at most 32 distinct ones, beyond that it would
 * show nothing. For very large meshes (over about 100,000 faces) ParaView samples the
 * label array; a cluster covering less than 0.1 % of the faces can then be missed by
 * that sampling and is drawn in the grey NaN colour.
 */
void ShapeDiameterRegisterColorDefaults();
