// A list of types, for generating every dispatch on a primitive's type from one list (scene/scene.h):
// variants, per-type containers and loops are written once over the list, never as a chain of
// `if constexpr (std::is_same_v<...>)` per type.
#pragma once

#include <cstddef>
#include <type_traits>

namespace twinray::math {

template <typename... Types>
struct TypeList {
    static constexpr std::size_t size = sizeof...(Types);

    // Target<Types...>, e.g. std::variant or std::tuple of the list.
    template <template <typename...> class Target>
    using apply = Target<Types...>;
    // TypeList<F<Types>...>.
    template <template <typename> class F>
    using map = TypeList<F<Types>...>;
    template <typename... More>
    using append = TypeList<Types..., More...>;

    template <typename T>
    static constexpr bool contains = (std::is_same_v<T, Types> || ...);

    // visit(std::type_identity<T>{}) for each type, in list order.
    template <typename Visit>
    static constexpr void for_each(Visit&& visit) {
        (visit(std::type_identity<Types>{}), ...);
    }
};

}  // namespace twinray::math
