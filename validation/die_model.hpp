#pragma once
// Werner's model of the two-dimensional loaded die (thesis Appendix II.1, eqs 2.A.1-2.A.4): a square whose
// centre of mass is moved a fraction f of the way from its centre to a corner, losing a factor eps^2 of
// its energy at each die-plane collision (one per quarter turn), captured in the well of the face it
// cannot climb out of. p_h is the probability that a high face lands up (a low face down).
//
// Energies are in units of m_d g a, a the die's half-side. The printed equations put the bottom of the
// high-face-down wells at f; the geometry of the die puts it at 2f (the centre of mass sits a(1 - f)
// above a low face and a(1 + f) above a high one), while the printed barrier heights E_l and E_M are the
// geometric ones. Both variants are computed; docs/validation.md discusses the difference.

namespace grainlab::validation {

enum class DieModelVariant {
  Printed,   // eqs 2.A.1-2.A.4 exactly as printed: high well at f m_d g
  Geometric  // the same capture argument with the die's own potential: high well at 2 f m_d g a
};

struct DieModel {
  double e_low = 0, e_mid = 0, e_high = 0;  // barriers at 45, 135/315 and 225 deg (eq. 2.A.1)
  double high_well = 0;                     // energy of the high-face-down rest state
  double window[4] = {0, 0, 0,
                      0};  // capture windows entering the 0, 90, 180, 270 deg wells (eps = 0: infinite)
  double p_h = 0.5;        // eq. 2.A.4
};

// f in [0, 1), eps in (0, 1). (At eps -> 0 the windows diverge; the limit is taken.)
DieModel die_model(double f, double eps, DieModelVariant variant);

}  // namespace grainlab::validation
