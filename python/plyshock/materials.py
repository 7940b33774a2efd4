"""Material presets (SI units: kg/m^3, m/s, Pa, K, J/kg/K), each with its source.

A deck names one with `preset:` and may override any field.  Models are named
by `type`; later issues add the solver's models (EOS, strength, failure) that
read these parameters.
"""
import copy
import math

# Linear Us-up Mie-Grueneisen: D. J. Steinberg, "Equation of state and strength
# properties of selected materials", LLNL UCRL-MA-106439 (1996).
# Johnson-Cook strength: G. R. Johnson & W. H. Cook, 7th Int. Symp. Ballistics
# (1983), reference strain rate 1/s, room temperature 294 K.
# Johnson-Cook failure: G. R. Johnson & W. H. Cook, Eng. Fract. Mech. 21 (1985).
# Shear moduli at ambient: Steinberg (1996).
PRESETS = {
    "OFHC-copper": {
        "density": 8930.0,
        "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02},
        "shear_modulus": 47.7e9,
        "strength": {"type": "johnson-cook", "A": 90e6, "B": 292e6, "n": 0.31, "C": 0.025, "m": 1.09, "T_melt": 1356.0},
        "specific_heat": 383.0,
        "failure": None,
        "source": "Steinberg UCRL-MA-106439 (EOS, G); Johnson & Cook 1983 (strength)",
    },
    # The same copper (Steinberg's EOS and G, specific heat 383 J/kg/K) with the
    # Zerilli-Armstrong fcc flow stress of OFHC copper from Zerilli & Armstrong,
    # J. Appl. Phys. 61 (1987) 1816: C2 890 MPa, C3 0.0028 1/K, C4 0.000115 1/K,
    # and C0 = delta sigma_G' + k l^(-1/2) = 65 MPa (the athermal stress with
    # the grain-size term of the OFHC copper of their Taylor-test comparison).
    # Quoted as the paper is usually cited; not checked against the paper's
    # table here, so check them before relying on them.
    "OFHC-copper-ZA": {
        "density": 8930.0,
        "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02},
        "shear_modulus": 47.7e9,
        "strength": {"type": "zerilli-armstrong-fcc", "C0": 65e6, "C2": 890e6, "C3": 0.0028, "C4": 0.000115},
        "specific_heat": 383.0,
        "failure": None,
        "source": "Steinberg UCRL-MA-106439 (EOS, G); Zerilli & Armstrong, J. Appl. Phys. 61 (1987) 1816 (strength)",
    },
    # ... and with the Mechanical Threshold Stress of Follansbee & Kocks, Acta
    # Metall. 36 (1988) 81, for copper, as Uintah ships them
    # (inputs/MPM/MaterialData/MTSPlasticAnnCopper.xml and MTSPlasticETPCu.xml,
    # identical): sigma_a 40 MPa, no intrinsic barrier (sigma_i 0), g_0e 1.6,
    # eps_dot_0e 1e7/s, p_e 2/3, q_e 1, theta_0 = 2390 MPa + 12 MPa ln(rate) +
    # 1.696 MPa s^1/2 sqrt(rate), alpha 2, sigma_es0 770 MPa, g_0es 0.2625,
    # eps_dot_es0 1e7/s, k/b^3 0.823 MPa/K; mu(T) = 47.7 GPa - 3.0 GPa/(exp(180 K/T) - 1).
    "OFHC-copper-MTS": {
        "density": 8930.0,
        "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02},
        "shear_modulus": 47.7e9,
        "strength": {"type": "mts", "sigma_a": 40e6, "mu_0": 47.7e9, "D": 3.0e9, "T_0": 180.0, "k_over_b3": 0.823e6,
                     "g_0e": 1.6, "eps_dot_0e": 1e7, "p_e": 2.0 / 3.0, "q_e": 1.0,
                     "a_0": 2390e6, "a_1": 12e6, "a_2": 1.696e6, "a_3": 0.0, "alpha": 2.0,
                     "g_0es": 0.2625, "eps_dot_es0": 1e7, "sigma_es0": 770e6, "sigma_i": 0.0},
        "specific_heat": 383.0,
        "failure": None,
        "source": "Steinberg UCRL-MA-106439 (EOS, G); Follansbee & Kocks, Acta Metall. 36 (1988) 81, constants as in Uintah's MTS copper data (strength)",
    },
    "4340-steel": {
        "density": 7810.0,
        "eos": {"type": "mie-gruneisen", "c0": 4578.0, "s": 1.33, "gamma0": 1.67},
        "shear_modulus": 77.5e9,
        "strength": {"type": "johnson-cook", "A": 792e6, "B": 510e6, "n": 0.26, "C": 0.014, "m": 1.03, "T_melt": 1793.0},
        "specific_heat": 477.0,
        "failure": None,
        "source": "Steinberg UCRL-MA-106439 (EOS, G); Johnson & Cook 1983 (strength)",
    },
    "6061-T6-aluminum": {
        "density": 2703.0,
        "eos": {"type": "mie-gruneisen", "c0": 5240.0, "s": 1.40, "gamma0": 1.97},
        "shear_modulus": 27.6e9,
        "source": "Steinberg UCRL-MA-106439 (EOS, G)",
    },
    "tantalum": {
        "density": 16690.0,
        "eos": {"type": "mie-gruneisen", "c0": 3410.0, "s": 1.20, "gamma0": 1.67},
        "shear_modulus": 69.0e9,
        "source": "Steinberg UCRL-MA-106439 (EOS, G)",
    },
    # Unidirectional IM7/8552 lamina: NASA CompDam test properties after Camanho
    # et al. (stiffness, in-situ strengths, fracture toughnesses G_XT, G_XC,
    # G_YT, G_SL); G23 = E2 / (2 (1 + nu23)); S23 = Yc / (2 tan 53 deg) from
    # CompDam's fracture-plane angle.  Density 1570 kg/m^3 from the Hexcel
    # HexPly 8552 product data sheet (cured laminate density of IM7/8552).
    # No EOS: we found no sourced Hugoniot of IM7/8552; without one the ply's
    # volumetric response is linear (its Reuss bulk modulus).
    "IM7/8552": {
        "density": 1570.0,
        "elastic": {"type": "orthotropic", "E1": 171.42e9, "E2": 9.08e9, "E3": 9.08e9,
                    "G12": 5.29e9, "G13": 5.29e9, "G23": 9.08e9 / (2 * 1.52),
                    "nu12": 0.32, "nu13": 0.32, "nu23": 0.52},
        "strengths": {"Xt": 2326.2e6, "Xc": 1200.1e6, "Yt": 62.3e6, "Yc": 199.8e6, "S12": 92.3e6,
                      "S23": 199.8e6 / (2 * math.tan(math.radians(53.0)))},
        "failure": {"type": "hashin", "G_ft": 133.3e3, "G_fc": 47.5e3, "G_mt": 277.0, "G_mc": 788.0},
        "source": "NASA CompDam (after Camanho) stiffness, strengths, fracture toughness; Hexcel 8552 data sheet density",
    },
}


def preset(name):
    """A deep copy of a preset's fields (without its source)."""
    d = copy.deepcopy(PRESETS[name])
    d.pop("source", None)
    return {k: v for k, v in d.items() if v is not None}
