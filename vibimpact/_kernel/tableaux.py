"""Butcher tableaux of the explicit Runge--Kutta methods, as data.

Each method is a :class:`Tableau`-like tuple of float64 arrays consumed by the one
step function in :mod:`vibimpact._kernel.integrator` ("methods as data", after SciPy's
``integrate/_ivp/rk.py``).  Row ``i`` of ``A`` holds the coefficients of stage ``i``;
stages past ``n_stages`` (DOP853 only) are the extra stages of the dense output.

The numerical values are those published with the methods:

* RK4 -- the classical fourth-order method (Kutta 1901).
* DP5 -- Dormand & Prince, "A family of embedded Runge-Kutta formulae",
  J. Comput. Appl. Math. 6 (1980) 19-26; its fourth-order continuous extension
  from Shampine, "Some practical Runge-Kutta formulas", Math. Comp. 46 (1986) 135-150.
* DOP853 -- Hairer, Norsett & Wanner, *Solving Ordinary Differential Equations I*,
  2nd ed., Springer 1993, Sec. II.10 (code DOP853), with its 7th-order dense output.

``tests/test_tableaux.py`` checks the order conditions of every tableau.
"""
import math

import numpy as np

# method identifiers used inside the kernel
RK4 = 0
DP5 = 1
DOP853 = 2
#: RK4's tableau at a fixed step with the switches inside the right-hand side and no
#: event location (:mod:`.noevents`: the era's integrator, to measure with)
RK4_NOEVENTS = 3

METHOD_IDS = {"rk4": RK4, "dp5": DP5, "dop853": DOP853, "rk4-fixed-noevents": RK4_NOEVENTS}
#: the fixed-step methods (no error estimate)
FIXED = (RK4, RK4_NOEVENTS)
#: classical order of each method (used by the step-size controller and the tests)
ORDER = {RK4: 4, DP5: 5, DOP853: 8, RK4_NOEVENTS: 4}

# --- RK4 -------------------------------------------------------------------------------
RK4_C = np.array([0.0, 0.5, 0.5, 1.0])
RK4_A = np.array([
    [0.0, 0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0, 0.0],
    [0.0, 0.5, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
])
RK4_B = np.array([1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0])

# --- Dormand-Prince 5(4) ----------------------------------------------------------------
DP5_C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0])
DP5_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0],
])
#: fifth-order weights (the last row of A: the method is FSAL)
DP5_B = DP5_A[6].copy()
#: b - b_hat, the embedded fourth-order error estimate (7 entries, FSAL stage last)
DP5_E = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0])
#: continuous extension: y(t0 + x h) = y0 + h * sum_j K_j * (P[j] @ [x, x^2, x^3, x^4])
DP5_P = np.array([
    [1.0, -2.8535800653862835, 3.0717434641059005, -1.1270175653862835],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 4.023133379230305, -6.249321565289, 2.675424484351598],
    [0.0, -3.7324019615885042, 10.068970589843675, -5.685526961588504],
    [0.0, 2.5548038301849423, -6.399112377351017, 3.5219323679207912],
    [0.0, -1.3744241142186024, 3.272657752246729, -1.7672812570757455],
    [0.0, 1.3824689317781436, -3.764937863556287, 2.382468931778144],
])

# --- DOP853 --------------------------------------------------------------------------
DOP853_NSTAGES = 12
#: nodes of the 12 stages, the FSAL stage and the 3 dense-output stages
DOP853_C = np.array([0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726, 0.3333333333333333, 0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0, 0.1, 0.2, 0.7777777777777778])
DOP853_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.05260015195876773, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0197250569845379, 0.0591751709536137, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.02958758547680685, 0.0, 0.08876275643042054, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894, -43.48988418106996, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423, -33.28821096898486, -0.020331201708508627, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259, 0.0, 0.0, 0.0, 0.0],
    [0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298, 0.0, 0.0, 0.0],
    [0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099, 0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325, 0.0, 0.0],
    [-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987, 0.0],
])
DOP853_B = DOP853_A[12, :12].copy()
#: error estimators of order 5 and 3 (13 entries, FSAL stage last)
DOP853_E5 = np.array([0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864, -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294, 0.0])
DOP853_E3 = np.array([-0.18980075407240762, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082, 0.0])
#: dense-output coefficients (rows: the 4th..7th interpolation polynomials)
DOP853_D = np.array([
    [-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727, -9.194632392478356, -4.436036387594894],
    [10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178, -9.35292435884448, 35.81684148639408],
    [19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412, 84.32040550667716, 11.99229113618279],
    [-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828, -39.17726167561544, -149.72683625798564],
])


# --- local error of a step that touches a Hertz contact's end -------------------------
def hertz_error_constants(B, C):
    """Local error constants of a method's steps at the ends of a Hertz contact.

    Next to a contact entry or exit the acceleration has a singular part ``c |t|^{3/2}``
    (the force ``k d^{3/2}`` with the penetration ``d`` linear in time; for the built-in
    rotor ``kh (R-1)^{3/2}``), so a step of size ``h`` that touches the surface has a
    velocity error ``gamma c h^{5/2}``, whatever the method's order: the step is a
    quadrature of that part with the weights ``B`` at the nodes ``C``.  Returns
    ``(gamma_in, gamma_out)``:

    * ``gamma_in``: the step starts on the surface (the first step of a contact),
      ``|sum_i b_i c_i^{3/2} - 2/5|``;
    * ``gamma_out``: the step runs into the surface (a contact's end) anywhere inside it,
      the largest ``|sum_i b_i (a - c_i)_+^{3/2} - a^{5/2}/(5/2)|`` over ``0 < a <= 1``.

    The embedded error estimate of such a step is no guide (for DOP853 it reports 0.29 of
    the true error at an entry, and as little as 0.006 of it at an exit inside a step),
    so the kernel sizes these steps from these constants instead, in a family's step cap
    (e.g. the built-in rotor's :func:`vibimpact._kernel.rotor.step_cap`).  Values: DOP853
    1.1e-4 and 1.5e-2, DP5 4.5e-4 and 5.6e-3.
    """
    b = np.asarray(B, dtype=np.float64)
    c = np.asarray(C, dtype=np.float64)[:b.size]
    # x ** 1.5 as x sqrt(x) and sums by math.fsum: the same bits on every processor
    gamma_in = abs(math.fsum(b * c * np.sqrt(c)) - 0.4)
    a = np.linspace(0.0, 1.0, 2001)[1:, None]
    d = np.clip(a - c[None, :], 0.0, None)
    q = np.array([math.fsum(row) for row in d * np.sqrt(d) * b[None, :]])
    gamma_out = float(np.abs(q - a[:, 0] * a[:, 0] * np.sqrt(a[:, 0]) / 2.5).max())
    return gamma_in, gamma_out


#: ``(gamma_in, gamma_out)`` of each adaptive method (see :func:`hertz_error_constants`)
HERTZ_ERROR = {DP5: hertz_error_constants(DP5_B, DP5_C),
               DOP853: hertz_error_constants(DOP853_B, DOP853_C)}
