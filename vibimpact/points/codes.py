"""Integer codes a point's results are stored with (CF ``flag_values``/``flag_meanings``)."""
from ..analysis.classify import Label

#: regime label -> integer code stored in datasets
REGIME_CODES = {Label.PERIODIC: 1, Label.QUASIPERIODIC: 2, Label.CHAOTIC: 3,
                Label.DIVERGED: 4, Label.UNSETTLED: 5}
REGIME_FLAGS = "periodic quasi_periodic chaotic diverged unsettled"

#: contact codes: free flight throughout, impacts (contact entries), or permanent contact
#: (in contact throughout, with no new impact: e.g. the built-in rotor rolling or whirling
#: on its retainer, R > 1 throughout)
CONTACT_NONE, CONTACT_IMPACTING, CONTACT_PERMANENT = 0, 1, 2
CONTACT_FLAGS = "none impacting permanent_contact"
