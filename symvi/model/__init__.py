"""The model layer: :class:`Model`, :class:`Stop`, named parameters, the paper's
preset and model files.  Nothing here imports any other layer of symvi."""
from ._constraint import Constraint as Constraint
from ._constraint import Signature as Signature
from ._file import ModelFileError as ModelFileError
from ._file import dumps as dumps
from ._file import load_model as load_model
from ._file import loads as loads
from ._file import model_from_dict as model_from_dict
from ._model import N_MAX as N_MAX
from ._model import Model as Model
from ._model import Stop as Stop
from ._model import Tangent as Tangent
from .parameters import Parameter as Parameter
