// The area of surface a photon lookup's disc holds, measured with probe rays.
//
// A density estimate divides the flux of the photons it counts by the area they could have
// landed on. Over a flat surface that fills the disc this is pi r^2; near an edge, a corner,
// a column or a molding, the surfaces that pass the lookup's guards (normal agreement, the
// flattened disc, visibility; photon_map.h) cover only part of it, and dividing by pi r^2
// reads dark by that share. PhotonEstimate::coverage infers the share from the photons'
// spread, which needs many photons; a progressive photon map's early, wide discs hold a
// photon or less on average (Sibenik under its sky: 0.3), as do final gathering's reads of a
// sparse global map at its largest radius, so there the share is measured:
// rays cast down through the disc along its normal, each counting the surface it first meets
// if a photon stored there would pass the lookup's guards: the area of the disc's plane those
// surfaces cover, as photons on a tilted face count by cos(tilt) per area of that plane
// (PhotonMap's estimates). The probes are a randomly shifted Fibonacci lattice over the
// disc, so each is uniform over it and the measured area is unbiased; over a surface that
// fills the disc every probe counts and the area is exactly pi r^2.
#pragma once
#include "photon_map.h"

namespace gi {

class Sampler;

inline constexpr int kDiscProbes = 16;       // a Fibonacci lattice (generator 13/16)
inline constexpr float kMinDiscShare = 0.25f;  // the least share of pi r^2 divided by

// The area of photon-holding surface in the disc of radius `radius` around the lookup (which
// must carry its scene), from kDiscProbes rays, or pi r^2 when the first half all count; never
// below kMinDiscShare of pi r^2, so that a rare bright photon on a sliver (a chain, a molding
// seen edge-on) is not multiplied by the whole disc's share of it.
float discArea(const PhotonLookup& at, float radius, Sampler& sampler, RayStats& stats);

// A k-nearest lookup's estimate read as a density over the surface in its disc: where k photons
// set the radius, their coverage says where the surface is (coverageCorrected); where photons fill
// the disc it stands; else (a disc at its largest radius with few photons) it is divided by the
// area discArea measures instead of pi r^2.
Color overSurfaceInDisc(const PhotonEstimate& e, int k, const PhotonLookup& at, Sampler& sampler, RayStats& stats);

}  // namespace gi
