// The one list of registration functions (see registry.h for why it is a list of calls and
// not self-registering objects). A new model, law or integrator adds its declaration and its
// call here, in the same order; test_registry.cpp checks that every register*(Registry&)
// defined in a *_registration.cpp is called below.
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

// Force models (src/core/model/*_registration.cpp).
void registerEdgeLengthModel(Registry&);
void registerHyperelasticModel(Registry&);
void registerStvkDisplacementModel(Registry&);
void registerTensorMassModel(Registry&);
void registerVirtualHexahedronModel(Registry&);  // src/core/model/adamss/
void registerAxialSpringModel(Registry&);        // src/core/model/adamss/
void registerTorsionSpringModel(Registry&);      // src/core/model/adamss/
void registerAxisFrictionModel(Registry&);       // src/core/model/adamss/
void registerVolumeSpringModel(Registry&);       // src/core/model/adamss/
void registerCavityModel(Registry&);             // src/core/model/adamss/
void registerLmsVolumeSpringModel(Registry&);   // src/core/model/adamss/
void registerActiveTensionModel(Registry&);      // src/core/model/adamss/
void registerAdamssTissuePresets(Registry&);     // src/core/model/adamss/
void registerMuscleGroupsModel(Registry&);
void registerCollisionModel(Registry&);
void registerFollowerPressureModel(Registry&);
// Material laws (src/core/material/*_registration.cpp).
void registerStvkLaw(Registry&);
void registerNeoHookeanLaw(Registry&);
void registerVolumeLaw(Registry&);
void registerHunterLaw(Registry&);
void registerHunterPolynomialLaw(Registry&);
void registerTeranMuscleLaw(Registry&);
void registerGuccioneLaw(Registry&);
// Integrators (src/core/integrate/*_registration.cpp).
void registerBackwardEuler(Registry&);
void registerNewtonian(Registry&);
void registerRadauIIA(Registry&);
void registerExplicitEuler(Registry&);
void registerAbm3(Registry&);
void registerRk4Adaptive(Registry&);
void registerQuasistatic(Registry&);

void registerBuiltIns(Registry& registry) {
  registerEdgeLengthModel(registry);
  registerHyperelasticModel(registry);
  registerStvkDisplacementModel(registry);
  registerTensorMassModel(registry);
  registerVirtualHexahedronModel(registry);
  registerAxialSpringModel(registry);
  registerTorsionSpringModel(registry);
  registerAxisFrictionModel(registry);
  registerVolumeSpringModel(registry);
  registerCavityModel(registry);
  registerLmsVolumeSpringModel(registry);
  registerActiveTensionModel(registry);
  registerAdamssTissuePresets(registry);
  registerMuscleGroupsModel(registry);
  registerCollisionModel(registry);
  registerFollowerPressureModel(registry);
  registerStvkLaw(registry);
  registerNeoHookeanLaw(registry);
  registerVolumeLaw(registry);
  registerHunterLaw(registry);
  registerHunterPolynomialLaw(registry);
  registerTeranMuscleLaw(registry);
  registerGuccioneLaw(registry);
  registerBackwardEuler(registry);
  registerNewtonian(registry);
  registerRadauIIA(registry);
  registerExplicitEuler(registry);
  registerAbm3(registry);
  registerRk4Adaptive(registry);
  registerQuasistatic(registry);
}

}  // namespace tt
